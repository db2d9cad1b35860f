// libFuzzer: game::parse_lesson, the reader of a lesson file, on arbitrary bytes; and what it accepts,
// modelled and scored (a designer's lesson drives both).
#include "game/training/form_score.hpp"
#include "game/lesson/lesson.hpp"
#include "tests/fuzz/fuzz_target.hpp"

using namespace ikebana;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const auto lesson = game::parse_lesson(fuzz::text_of(data, size), fuzz::label);
    fuzz::expect_named(lesson);
    if (lesson && lesson->scoring == "form") {
        const game::KenzanFootprint kenzan;
        (void)game::score_form(*lesson, game::model_arrangement(*lesson, kenzan), kenzan);
    }
    return 0;
}
