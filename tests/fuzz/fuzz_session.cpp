// libFuzzer: the readers of a lesson session on record (session.json and commands.csv, what `lesson
// replay DIR` reads) and of the window's state (`ikebana --state-out`, what `lesson demo --window`
// reads back), on arbitrary bytes. The first byte picks the reader.
#include "game/session/lesson_session.hpp"
#include "game/session/window_state.hpp"
#include "tests/fuzz/fuzz_target.hpp"

using namespace ikebana;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size == 0) return 0;
    const auto text = fuzz::text_of(data + 1, size - 1);
    switch (data[0] % 3) {
    case 0: fuzz::expect_named(game::parse_session(text, fuzz::label)); break;
    case 1: fuzz::expect_named(game::parse_session_commands(text, fuzz::label)); break;
    default: {
        const auto state = game::parse_window_state(text, fuzz::label);
        fuzz::expect_named(state);
        // What it accepts is written again and read back the same.
        if (state) {
            const auto again = game::parse_window_state(game::window_state_json(*state), fuzz::label);
            if (!again || again->frame != state->frame || again->flowers.size() != state->flowers.size()) std::abort();
        }
        break;
    }
    }
    return 0;
}
