#include "game/lesson/teacher.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <glm/gtc/quaternion.hpp>

namespace ikebana::game {

namespace {

constexpr double pi = 3.14159265358979323846;
constexpr double hand_speed_m_s = 0.25;

// Device angles (about x, then y, then z: systems::device_turn's order) for a turn.
glm::dvec3 device_angles(const glm::dquat& q) {
    const glm::dmat3 m = glm::mat3_cast(q); // m[column][row]
    const double y = std::asin(std::clamp(-m[0][2], -1.0, 1.0));
    const double x = std::atan2(m[1][2], m[2][2]);
    const double z = std::atan2(m[0][1], m[0][0]);
    return {x, y, z};
}

// The turn taking unit vector a onto unit vector b by the shortest way.
glm::dquat turn_between(glm::dvec3 a, glm::dvec3 b) {
    const glm::dvec3 axis = glm::cross(a, b);
    const double s = glm::length(axis);
    const double c = glm::dot(a, b);
    if (s < 1e-12) return c > 0 ? glm::dquat{1, 0, 0, 0} : glm::angleAxis(pi, glm::dvec3{0, 0, 1});
    return glm::angleAxis(std::atan2(s, c), axis / s);
}

// From this tilt on, a stem is set at its band's upper edge (see teach).
constexpr double low_stem_rad = 60.0 * pi / 180.0;

class Teacher {
public:
    Teacher(Classroom& room, TeacherHand& hand, DemoResult& result, const DemoOptions& options, std::size_t total_steps)
        : room_(room), hand_(hand), result_(result), options_(options), total_(total_steps) {}

    void say(const std::string& what) {
        result_.steps.push_back({room_.now_s(), what});
        if (options_.progress) options_.progress(result_.steps.size(), total_, what);
    }
    void wait(double seconds) { room_.wait(seconds); }

    void move_to(glm::dvec3 target, double speed = hand_speed_m_s) {
        const glm::dvec3 from = hand_.position();
        const double distance = glm::length(target - from);
        const double step = hand_.step_s();
        const int steps = std::max({1, static_cast<int>(std::ceil(distance / (speed * step))), static_cast<int>(std::ceil(distance / hand_.step_m()))});
        for (int i = 1; i <= steps; ++i) {
            hand_.go(from + (target - from) * (static_cast<double>(i) / steps));
            wait(step);
        }
    }
    void turn_to(glm::dvec3 angles, double seconds) {
        const glm::dvec3 from = hand_.angles();
        const int steps = std::max(1, static_cast<int>(seconds / hand_.turn_step_s()));
        for (int i = 1; i <= steps; ++i) {
            hand_.turn(from + (angles - from) * (static_cast<double>(i) / steps));
            wait(hand_.turn_step_s());
        }
    }
    void press(bool down) {
        hand_.grab(down);
        wait(0.05);
    }

    // One stem of the model: from the table, cut, turned, into the kenzan at its place, let go.
    bool place(std::size_t flower, const std::string& role, const ArrangementStem& target) {
        const double in_pins = room_.pin_height_m();
        const double keep = target.length_m + in_pins;
        const SeenFlower lying = room_.flower(flower);
        if (lying.points_m.size() < 2) {
            say(role + ": the " + target.species + " cannot be seen");
            return false;
        }
        const double cut = lying.length_m - keep;
        // Take it a little above where its new bottom will be: a hand holds a stem near its base to push it in.
        const double grip_from_new_bottom = std::min(0.06, 0.3 * keep);
        // On the stem as it lies (a branch's curve lifts it off the line between its ends).
        double to_go = std::max(0.0, cut) + grip_from_new_bottom;
        glm::dvec3 grip_at = lying.points_m.back();
        for (std::size_t i = 1; i < lying.points_m.size(); ++i) {
            const double segment = glm::length(lying.points_m[i] - lying.points_m[i - 1]);
            if (to_go <= segment) {
                grip_at = lying.points_m[i - 1] + (lying.points_m[i] - lying.points_m[i - 1]) * (to_go / segment);
                break;
            }
            to_go -= segment;
        }
        say(role + ": take the " + target.species + " from the table");
        hand_.look();
        move_to(grip_at + glm::dvec3{0, 0, 0.06});
        move_to(grip_at);
        press(true);
        if (room_.held() != flower) {
            say(role + ": missed the " + target.species);
            press(false);
            return false;
        }
        move_to(hand_.position() + glm::dvec3{0, 0, 0.22});
        char what[256];
        if (cut > 0.001) {
            std::snprintf(what, sizeof what, "%s: cut it to %.0f mm (%.0f above the kenzan, %.0f in the pins)", role.c_str(), keep * 1e3, target.length_m * 1e3,
                          in_pins * 1e3);
            say(what);
            hand_.cut(keep);
            wait(0.3);
            const double now = room_.flower(flower).length_m;
            if (std::abs(now - keep) > 0.002) {
                std::snprintf(what, sizeof what, "%s: it was cut to %.0f mm, not %.0f", role.c_str(), now * 1e3, keep * 1e3);
                say(what);
            }
        }
        // Turn it: first the held stem's own direction onto the role's, then correct by what it shows
        // (a head bends a stem, a branch has its curve).
        const glm::dvec3 want = lesson_direction(target.tilt_rad, target.azimuth_rad);
        std::snprintf(what, sizeof what, "%s: tilt it %.0f° toward the %s", role.c_str(), target.tilt_rad * 180 / pi, direction_words(target.azimuth_rad).c_str());
        say(what);
        // A branch's curve, which lay bowing up on the table, is turned to hang down: a curve held any
        // other way rolls down under its own weight once let go (a stem has no stiffness against
        // twisting in the model), so that is where it settles. The stem's axis lay along +x, its curve
        // rising toward +z: x goes to the role's direction, z to straight down across it.
        glm::dvec3 down = glm::dvec3{0, 0, -1} - glm::dot(glm::dvec3{0, 0, -1}, want) * want;
        down = glm::length(down) > 1e-6 ? glm::normalize(down) : glm::dvec3{0, -1, 0};
        glm::dquat turn = glm::quat_cast(glm::dmat3(want, glm::cross(down, want), down));
        for (int round = 0; round < 4; ++round) {
            const auto x = room_.flower(flower).points_m;
            const glm::dvec3 now = glm::normalize(x.back() - x.front());
            if (round > 0) turn = turn_between(now, want) * turn;
            turn_to(device_angles(turn), round == 0 ? 1.5 : 0.5);
            wait(0.4);
        }
        // Over its place, just above the pins; then straight down into them.
        const glm::dvec3 kenzan = room_.kenzan_origin_m();
        const glm::dvec3 base = kenzan + glm::dvec3(target.base_m, 0.0);
        say(role + ": over its place in the kenzan");
        for (int round = 0; round < 3; ++round) {
            const glm::dvec3 bottom = room_.flower(flower).points_m.front();
            const glm::dvec3 goal = base + glm::dvec3{0, 0, in_pins + 0.008};
            move_to(hand_.position() + (goal - bottom), 0.15);
            wait(0.2);
        }
        say(role + ": push it into the pins");
        // Until its end's lowest edge is a hair above the plate: pushed further, the hand would bend the
        // stem against the plate, and it would spring when let go. The hand never goes lower than where
        // the stem, hanging free in it now, would touch the plate: the pins hold the stem back while the
        // hand goes on (in the window the hand moves in frame-sized steps and sees the stem a frame or
        // two late), and rounds that asked again and again drove the hand centimetres under its stem,
        // which then bent against the plate and tore out of the pins.
        const double radius = 0.5 * lying.diameter_m;
        const double hand_above_bottom = hand_.position().z - room_.flower(flower).points_m.front().z;
        for (int round = 0; round < 3; ++round) {
            const auto x = room_.flower(flower).points_m;
            const glm::dvec3 axis = glm::normalize(x[1] - x[0]);
            const double edge_drop = radius * std::sqrt(std::max(0.0, 1.0 - axis.z * axis.z));
            const double lower_by = x.front().z - edge_drop - (kenzan.z + 0.0003);
            const double lowest = kenzan.z + 0.0003 + edge_drop + hand_above_bottom;
            const double to_z = std::max(hand_.position().z - lower_by, lowest);
            if (hand_.position().z - to_z < 0.0005) break;
            move_to({hand_.position().x, hand_.position().y, to_z}, 0.03);
            wait(0.2);
        }
        wait(1.0);
        say(role + ": let go");
        press(false);
        // Away sideways from the stem, clear of its leaves (a hand drawn through them tipped a short
        // chrysanthemum), then up.
        const glm::dvec3 side = glm::normalize(glm::cross(want, glm::dvec3{0, 0, 1}) + glm::dvec3{1e-9, 0, 0});
        move_to(hand_.position() + side * 0.08, 0.1);
        move_to(hand_.position() + glm::dvec3{0, 0, 0.1}, 0.2);
        wait(1.0);
        // What the physics made of it, said as the HUD would.
        const SeenFlower now = room_.flower(flower);
        const glm::dvec3 bottom = now.points_m.front() - kenzan;
        const double tilt = std::acos(std::clamp(glm::normalize(now.points_m.back() - now.points_m.front()).z, -1.0, 1.0)) * 180 / pi;
        if (now.fallen && now.yield_holding_nm > 0.0)
            std::snprintf(what, sizeof what, "%s: FELL: %s (the pins first gave way holding %.1f mN m under %.1f, %u pins, %.1f mm deep)", role.c_str(),
                          components::fall_words(now.fall_reason), now.yield_holding_nm * 1e3, now.yield_gravity_nm * 1e3, now.pins, now.depth_m * 1e3);
        else if (now.fallen) std::snprintf(what, sizeof what, "%s: FELL: %s (its line now %.0f° from vertical)", role.c_str(), components::fall_words(now.fall_reason), tilt);
        else if (now.in_kenzan) std::snprintf(what, sizeof what, "%s: stands in the kenzan, %.0f mm deep in %u pins, %.0f° from vertical", role.c_str(), now.depth_m * 1e3, now.pins, tilt);
        else std::snprintf(what, sizeof what, "%s: not in the pins: its bottom is at [%.0f, %.0f, %.0f] mm from the kenzan's centre", role.c_str(), bottom.x * 1e3, bottom.y * 1e3, bottom.z * 1e3);
        say(what);
        return now.in_kenzan && !now.fallen;
    }

private:
    Classroom& room_;
    TeacherHand& hand_;
    DemoResult& result_;
    const DemoOptions& options_;
    std::size_t total_;
};

} // namespace

void teach(const LessonDef& lesson, const Arrangement& model, Classroom& room, TeacherHand& hand, DemoResult& result, const DemoOptions& options) {
    Teacher teacher(room, hand, result, options, model.stems.size() * 6 + 1);
    teacher.wait(0.5); // the materials settle on the table
    const double in_pins = room.pin_height_m();
    std::vector<bool> used(room.flower_count(), false);
    std::vector<SeenFlower> materials;
    for (std::size_t i = 0; i < room.flower_count(); ++i) materials.push_back(room.flower(i));
    for (const auto& target : model.stems) {
        // The shortest unused material of the species that is long enough.
        std::optional<std::size_t> pick;
        for (std::size_t i = 0; i < materials.size(); ++i) {
            if (used[i] || materials[i].species != target.species) continue;
            if (materials[i].length_m < target.length_m + in_pins) continue;
            if (!pick || materials[i].length_m < materials[*pick].length_m) pick = i;
        }
        if (!pick) {
            teacher.say(target.role + ": no " + target.species + " long enough is left on the table");
            continue;
        }
        used[*pick] = true;
        // A low stem sinks once let go (its head's weight on a long lever; the hand opens at once and the
        // stem whips down before it settles): a teacher sets it higher than the form's angle. Measured
        // with the 258 mm chrysanthemum of Sogetsu's hikae (75 +-10 degrees): held at 75 it sank to
        // 87-91 and lay flat; at 65, to 68 in one lesson and 87 in the other; at 60, to 63 in both.
        ArrangementStem aimed = target;
        const auto role = std::find_if(lesson.stems.begin(), lesson.stems.end(), [&](const MainStemDef& m) { return m.role == target.role; });
        if (role != lesson.stems.end() && role->tilt_rad.target >= low_stem_rad) aimed.tilt_rad = role->tilt_rad.target - 1.5 * role->tilt_rad.tolerance;
        const auto held_at = options.tilt_deg.find(target.role);
        if (held_at != options.tilt_deg.end()) aimed.tilt_rad = held_at->second * pi / 180;
        if (aimed.tilt_rad != target.tilt_rad) {
            char why[160];
            std::snprintf(why, sizeof why, "%s: %s: held at %.0f° for the form's %.0f°", target.role.c_str(),
                          held_at != options.tilt_deg.end() ? "as asked" : "a low stem sinks once let go", aimed.tilt_rad * 180 / pi, target.tilt_rad * 180 / pi);
            teacher.say(why);
        }
        // A stem that tipped over, or slipped from the hand, is taken again once, as a teacher would.
        if (!teacher.place(*pick, target.role, aimed)) {
            teacher.say(target.role + ": it did not stand: take it again");
            teacher.place(*pick, target.role, aimed);
        }
    }
    teacher.say("done: let the arrangement settle");
    teacher.wait(2.0);
}

} // namespace ikebana::game
