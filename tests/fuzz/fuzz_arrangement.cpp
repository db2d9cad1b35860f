// libFuzzer: game::parse_arrangement (`lesson score --arrangement`) on arbitrary bytes, and what it
// accepts scored against a shipped lesson with every rule (role assignment, crossings, the line at
// the water walk the stems' paths).
#include "game/training/form_score.hpp"
#include "game/lesson/lesson.hpp"
#include "tests/fuzz/fuzz_target.hpp"

using namespace ikebana;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static const auto upright = game::load_lesson("sogetsu_basic_upright");
    static const auto shoka = game::load_lesson("ikenobo_shoka_shofutai");
    if (!upright || !shoka) std::abort();
    const auto arrangement = game::parse_arrangement(fuzz::text_of(data, size), fuzz::label);
    fuzz::expect_named(arrangement);
    if (arrangement) {
        const game::KenzanFootprint kenzan;
        for (const auto* lesson : {&*upright, &*shoka}) {
            const auto scored = game::score_form(*lesson, *arrangement, kenzan, fuzz::label);
            fuzz::expect_named(scored);
            if (scored && !(scored->score >= 0.0 && scored->score <= 100.0)) std::abort();
            if (scored) (void)game::parse_arrangement(scored->json(), fuzz::label);
        }
    }
    return 0;
}
