#pragma once
// Insertion into the kenzan (paper sections 2.5 and 3): what each flower remembers of its insertions,
// which pins are in its stem now, and the resistance model its species gives it. SI units.
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace ikebana::components {

// One pin inside the stem, with its contact length split by pin part (Figure 10: cone tip, cylindrical
// trunk) and, for a hard branch, by tissue (Figure 11: cortex, pith).
struct PinContact {
    std::int32_t pin;          // row * columns + column
    double tip_m;              // length of the cone inside the stem
    double trunk_m;            // length of the trunk inside the stem
    double tip_in_pith_m;      // hard branch: parts of tip_m / trunk_m inside the pith
    double trunk_in_pith_m;
    double force_n;            // this pin's resistance now
    double lever_m;            // its lever arm about the tipping edge (holding moment)
};

struct PinEngagement {
    std::vector<PinContact> pins;
    double depth_m;               // how far the stem bottom is below the pin tips
    double resistance_n;          // sum of the pins' forces: what resists insertion and withdrawal
    double holding_moment_nm;     // what the pins can resist (Eq. 7, left side, made a moment)
    double gravity_moment_nm;     // m g r cos(theta) about the tipping edge (Eq. 7, right side)
    bool in_kenzan;
};

// The pins an insertion met, kept without allocating (it grows on the 1 kHz lane, one pin at a time):
// up to `capacity` distinct pins, more than a stem as thick as a thumb touches on the standard kenzan;
// past that the first ones are kept and `more` counts the adds that did not fit.
struct PinSet {
    static constexpr std::size_t capacity = 64;
    std::array<std::int32_t, capacity> pin{};
    std::uint32_t count = 0;
    std::uint32_t more = 0;
    [[nodiscard]] std::size_t size() const noexcept { return count; }
    [[nodiscard]] const std::int32_t* begin() const noexcept { return pin.data(); }
    [[nodiscard]] const std::int32_t* end() const noexcept { return pin.data() + count; }
    [[nodiscard]] bool contains(std::int32_t p) const noexcept {
        for (std::uint32_t i = 0; i < count; ++i) {
            if (pin[i] == p) return true;
        }
        return false;
    }
    void add(std::int32_t p) noexcept {
        if (contains(p)) return;
        if (count < capacity) pin[count++] = p;
        else ++more;
    }
};

// What a flower's insertion history holds without allocating on the lane: reserved as the flower is
// made (a session of a hundred insertions of one stem is far past any the paper's flowers survive).
inline constexpr std::size_t insertion_records_reserved = 128;
inline constexpr std::size_t engaged_pins_reserved = 64;

struct InsertionRecord {
    std::uint32_t number;         // 1-based, counted on the current stem end
    std::int64_t start_us;
    double max_depth_m;
    double max_resistance_n;
    double max_pin_force_n;
    std::uint32_t max_pins;
    double angle_deg;             // stem elevation against the horizontal when it entered
    bool reused_hole;             // entered where an earlier insertion of this end had been
    bool broke;                   // the bottom split during this insertion
    PinSet pins;                  // every pin that was inside the stem during this insertion
};

// The flower's own history (kept by insertion_tracking_system).
struct InsertionHistory {
    std::uint32_t insertions;        // on the current stem end: what deterioration counts
    std::uint32_t insertions_total;  // over the flower's life, across cuts
    bool bottom_broken;
    std::uint32_t cuts;
    std::int64_t cut_at_us;          // simulation time of the last cut (or of the flower's creation)
    std::vector<InsertionRecord> records;
    std::vector<glm::dvec2> holes;   // where the current end entered the kenzan (x, y)
    bool left_pins;                  // the end has come out of the pins (at left_pins_us)
    std::int64_t left_pins_us;
    double out_rise_m;               // how far above the pin tips the end has risen since it left them
    glm::dvec2 left_at_m;            // where the end's bottom was (x, y) when it left them
    bool entry_counted;              // this entry into the pins has been decided (an insertion, or a stem set in)
    bool entry_held;                 // a hand held the stem at some moment of this entry, before it was decided
};

enum class ResistanceKind : std::uint8_t { soft_table, hard_eq6 };

// A multiplicative extension of the soft-branch deterioration, fitted from measured data:
// factor = exp(sum of terms). Forms: "linear", "log", "saturating", "power", "step", "category".
struct DeteriorationTerm {
    std::string covariate;        // a column name of the measured data, or "insertion"
    std::string form;
    double coefficient;
    double scale;                 // log: shift; saturating: length; step: threshold; power: exponent
    std::string category;         // for "category": which value the coefficient applies to
    double origin;                // the form is evaluated at (covariate - origin)
    // The covariate is clamped into [range_low, range_high] (the values the term was fitted on) so a
    // fitted curve is never extrapolated; equal bounds: no clamp.
    double range_low;
    double range_high;
    // An interaction: the term's basis times (times_covariate - times_origin), that covariate clamped
    // into [times_low, times_high] (equal: no clamp); empty: none. The term's effect then grows or
    // shrinks with the second covariate.
    std::string times_covariate;
    double times_origin;
    double times_low;
    double times_high;
};

// The species' resistance model as the systems use it (copied from the species file on spawn).
struct PinResistance {
    ResistanceKind kind;
    // soft_table: resistance per metre of pin by insertion count, already expanded by the
    // deterioration model (index k-1 for the k-th insertion; the last value holds from then on).
    std::vector<double> n_per_m_by_insertion;
    std::vector<DeteriorationTerm> extension;
    // true: the extension multiplies only the resistance to the push (what a gauge measures as the stem
    // slides in), not what holds a stem at rest in the pins (its holding moment, the base model's).
    // Fitted to pushes and holding too, it held the paper's sunflowers for 16 insertions, not 5.8.
    bool extension_push_only;
    // Terms on the holding alone (a species' "applies_to": "hold" terms): exp(sum) multiplies what holds
    // a stem at rest (the holding moment), never the push's resistance. Empty: none.
    std::vector<DeteriorationTerm> hold_extension;
    // hard_eq6 (Table 1)
    double cortex_tip_n_per_m;
    double cortex_trunk_n_per_m;
    double pith_tip_n_per_m;
    double pith_trunk_n_per_m;
    double pith_diameter_m;
    // breakage (section 3.1)
    std::vector<double> break_probability_by_insertion;
    double broken_holding_factor;
    double broken_seat_loss_m;
};

// Deterministic random numbers in the world state (so the state hash covers them): splitmix64.
struct RandomStream {
    std::uint64_t state;
};

} // namespace ikebana::components

namespace ikebana::components {

// Why a stem counts as fallen: one definition for the HUD, the `sim` summary and the score.
enum class FallReason : std::uint8_t {
    none,
    tipped,    // the pins gave way: its end, or its whole line while they gave, turned past the fall angle
    lies_flat, // its line from bottom to top is within the lying angle of level: it lies, it does not stand
    dropped,   // its top is hardly higher than its bottom (a tenth of its length): it hangs over
};

// The words the HUD and the summary use for it.
inline const char* fall_words(FallReason reason) {
    switch (reason) {
    case FallReason::tipped: return "tipped over";
    case FallReason::lies_flat: return "lies flat";
    case FallReason::dropped: return "it hangs over, its top hardly above its bottom";
    case FallReason::none: break;
    }
    return "";
}

// How the kenzan holds a released stem: the bottom point stays where it entered and the first segment
// is held in direction by a root hinge whose moment is capped at the pins' holding moment. Beyond
// the cap the hinge yields and the stem tips over about the kenzan (Eq. 7 made dynamic).
struct KenzanGrip {
    bool engaged;
    // Its end's direction in the pins when it was released. Tipped is measured from this to the root
    // hinge's direction now, which moves only where the pins give way: a flower whose own stem sags
    // under its head (a hikae at 70 degrees sinks 15 degrees between its end and its top) has not
    // tipped; if it sinks to level it lies flat.
    glm::dvec3 entry_axis;
    glm::dvec3 entry_line;       // its line from bottom to top then
    double holding_moment_nm;    // the cap, from the pins
    bool fallen;                 // see fall_reason
    FallReason fall_reason;
    double release_height_m;     // its top above its bottom when it was released
    // Why it fell, for the summary and the HUD: a fallen stem leans on more pins and can show a
    // positive margin, so the moments when the pins first gave way are kept, and when it tipped.
    bool yielded;                // the pins have given way at least once since it was released
    double yield_holding_nm;     // at that first give
    double yield_gravity_nm;
    std::int64_t fell_at_us;     // simulated time it passed fall_angle
};

// How many hands hold the flower now (scripted or haptic). An insertion is a held stem entering the
// pins; a stem that falls or slides onto them is not one, and a held stem is not gripped by the kenzan.
struct Grasp {
    std::uint8_t hands;
};

// A scripted hand that inserts and withdraws a stem (the experiment, tests, demos; the haptics issue
// puts real hands in its place). It holds the stem straight along `axis` and moves it vertically.
struct ScriptedInsertion {
    enum class Stage : std::uint8_t { idle, pushing, released, withdrawing, lifted };
    Stage stage;
    glm::dvec3 axis;             // unit, bottom to top, kept while held
    glm::dvec3 bottom_m;         // where the hand holds the bottom now
    double speed_m_s;
    double stop_z_m;             // pushing stops when the stem's lowest point reaches this height
    double max_push_n;           // or when the pins resist more than the hand pushes
    double lift_to_z_m;          // withdrawing stops when the bottom is this high
};

} // namespace ikebana::components

namespace ikebana::components {

// A request to cut this much off the stem end (the trainee's scissors; scripted in tests). The
// cutting system shortens the stem, and the fresh end has no history: no break, no holes, no wear.
struct CutRequest {
    double length_m;
};

// On a hand: prune where it is (the trainee's secateurs at the cube). The twig whose stem comes nearest
// the cube within its reach is cut off at its fork, or the leaf or blossom nearest it stripped: either
// falls (a Cutting). Consumed by the pruning system.
struct PruneRequest {
    std::uint8_t hand = 0;
};

// A piece pruned off a flower, loose: a twig (with its own twigs, leaves and blossoms) or a stripped leaf,
// a stem of its own that falls to the table. Drawn in the flower's colours.
struct Cutting {
    std::string species;
};

} // namespace ikebana::components
