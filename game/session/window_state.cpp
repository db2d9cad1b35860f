#include "game/session/window_state.hpp"

#include <cstdio>
#include <type_traits>
#include <utility>

#include <nlohmann/json.hpp>

#include "engine/assets/files.hpp"
#include "engine/assets/json_checker.hpp"

namespace ikebana::game {

using Json = nlohmann::json;

void take_layout(WindowState& state, const PointerView& view, glm::dvec2 window_px, const components::FrameSnapshot& frame,
                 const std::vector<WindowState::Box>& panels) {
    auto& out = state.layout;
    out = {};
    const render::ScreenLayout screen = view.layout(window_px);
    const std::vector<int> eyes = screen.areas() == 2 ? std::vector<int>{-1, 1} : std::vector<int>{0};
    for (const int eye : eyes) {
        const double left = eye > 0 ? screen.area_width_px() : 0.0;
        for (auto p : panels) {
            p.eye = eye;
            p.min_px.x += left;
            out.panels.push_back(std::move(p));
        }
        const glm::dvec2 view_min{screen.scene_left_px(eye), 0.0}, view_size{screen.scene_width_px(), screen.height_px()};
        out.views.push_back({"view", eye, view_min, view_size});
        // A box round what the eye shows of these points, cut to its view (none: nothing of it shows).
        const auto box = [&](const std::string& name, const std::vector<glm::dvec3>& points_m) {
            glm::dvec2 lo{1e30}, hi{-1e30};
            for (const auto& p : points_m) {
                if (const auto px = drawn_px(view, window_px, eye, p)) {
                    lo = glm::min(lo, *px);
                    hi = glm::max(hi, *px);
                }
            }
            lo = glm::max(lo, view_min);
            hi = glm::min(hi, view_min + view_size);
            if (hi.x > lo.x && hi.y > lo.y) out.scene.push_back({name, eye, lo, hi - lo});
        };
        if (frame.kenzan) {
            const auto& k = *frame.kenzan;
            const glm::dvec3 lo = k.pin_base(0, 0) - glm::dvec3{0.5 * k.pitch_m, 0.5 * k.pitch_m, 0.0};
            const glm::dvec3 hi = k.pin_base(k.columns - 1, k.rows - 1) + glm::dvec3{0.5 * k.pitch_m, 0.5 * k.pitch_m, k.pin_height_m()};
            std::vector<glm::dvec3> corners;
            for (int c = 0; c < 8; ++c) corners.push_back({c & 1 ? hi.x : lo.x, c & 2 ? hi.y : lo.y, c & 4 ? hi.z : lo.z});
            box("kenzan", corners);
        }
        for (std::size_t i = 0; i < frame.flowers.size(); ++i) {
            const auto& f = frame.flowers[i];
            if (f.in_kenzan && !f.fallen) box("stem " + std::to_string(i) + ": " + f.species, f.points_m);
        }
    }
}

void take_snapshot(WindowState& state, const components::FrameSnapshot& frame) {
    state.sim_time_us = frame.sim_time_us;
    for (int h = 0; h < 2; ++h) {
        const auto& hand = frame.hands[h];
        state.hands[h] = {hand.holding,   hand.held_flower,  hand.position_m, hand.device_m, hand.force_n, hand.sent.sent_n,
                          hand.sent.pushes, components::device_link_words(hand.link)};
    }
    state.flowers.resize(frame.flowers.size());
    for (std::size_t i = 0; i < frame.flowers.size(); ++i) {
        const auto& f = frame.flowers[i];
        state.flowers[i] = {f.species, f.points_m, f.diameter_m, f.in_kenzan, f.fallen, f.fall_reason, f.fall_yield_holding_nm, f.fall_yield_gravity_nm,
                            f.pins_engaged, f.depth_m};
    }
    if (frame.kenzan) {
        state.kenzan_origin_m = frame.kenzan->origin_m;
        state.kenzan_pin_height_m = frame.kenzan->pin_height_m();
    }
}

namespace {
Json vec(glm::dvec3 v) { return Json::array({v.x, v.y, v.z}); }
Json vec(glm::dvec2 v) { return Json::array({v.x, v.y}); }

// A reader's helpers: each names the field it could not read.
struct Reader {
    std::string error;
    template <typename T>
    T get(const Json& j, const char* key, T fallback = {}) {
        if (!error.empty()) return fallback;
        if (!j.is_object() || !j.contains(key)) {
            error = std::string("no field '") + key + "'";
            return fallback;
        }
        try {
            // An integer field takes integers in its type's range only: nlohmann converts a float (or
            // an integer too long for 64 bits, read as one) with a plain cast, undefined out of range
            // (a fuzzer's "pins_engaged": 666666666666666666666666666666666668).
            if constexpr (std::is_integral_v<T> && !std::is_same_v<T, bool>) {
                const Json& v = j.at(key);
                const bool fits = v.is_number_unsigned()  ? std::in_range<T>(v.get<std::uint64_t>())
                                  : v.is_number_integer() ? std::in_range<T>(v.get<std::int64_t>())
                                                          : false;
                if (!fits) {
                    error = std::string("field '") + key + "' should be an integer" + (v.is_number() ? " in range" : "");
                    return fallback;
                }
            }
            return j.at(key).get<T>();
        } catch (const Json::exception&) {
            error = std::string("field '") + key + "' has the wrong type";
            return fallback;
        }
    }
    template <int N>
    glm::vec<N, double> vector(const Json& j, const char* key) {
        const auto v = get<std::vector<double>>(j, key);
        glm::vec<N, double> out{0.0};
        if (!error.empty()) return out;
        if (v.size() != N) {
            error = std::string("field '") + key + "' should have " + std::to_string(N) + " numbers";
            return out;
        }
        for (int i = 0; i < N; ++i) out[i] = v[static_cast<std::size_t>(i)];
        return out;
    }
};
} // namespace

std::string window_state_json(const WindowState& s) {
    Json j;
    j["frame"] = s.frame;
    j["input_read_at_us"] = s.input_read_at_us;
    j["sim_time_us"] = s.sim_time_us;
    j["window_px"] = vec(s.window_px);
    j["cursor_px"] = vec(s.cursor_px);
    j["pointer"] = {{"active_hand", s.active_hand}, {"px_per_m", vec(s.px_per_m)}};
    j["hands"] = Json::array();
    for (const auto& h : s.hands) {
        j["hands"].push_back({{"holding", h.holding},
                              {"held_flower", h.held_flower},
                              {"position_m", vec(h.position_m)},
                              {"device_m", vec(h.device_m)},
                              {"force_asked_n", vec(h.force_asked_n)},
                              {"force_sent_n", vec(h.force_sent_n)},
                              {"force_pushes", h.pushes},
                              {"link", h.link}});
    }
    j["flowers"] = Json::array();
    for (const auto& f : s.flowers) {
        Json points = Json::array();
        for (const auto& p : f.points_m) points.push_back(vec(p));
        j["flowers"].push_back({{"species", f.species},
                                {"points_m", std::move(points)},
                                {"diameter_m", f.diameter_m},
                                {"in_kenzan", f.in_kenzan},
                                {"fallen", f.fallen},
                                {"fall_reason", static_cast<int>(f.fall_reason)},
                                {"yield_holding_nm", f.yield_holding_nm},
                                {"yield_gravity_nm", f.yield_gravity_nm},
                                {"pins_engaged", f.pins_engaged},
                                {"depth_m", f.depth_m}});
    }
    if (s.kenzan_origin_m) j["kenzan"] = {{"origin_m", vec(*s.kenzan_origin_m)}, {"pin_height_m", s.kenzan_pin_height_m}};
    j["screen"] = s.screen;
    if (!s.display.empty()) j["display"] = s.display;
    Json buttons = Json::array();
    for (const auto& b : s.buttons) buttons.push_back({{"label", b.label}, {"min_px", vec(b.min_px)}, {"max_px", vec(b.max_px)}});
    j["buttons"] = buttons;
    const auto boxes = [](const std::vector<WindowState::Box>& list) {
        Json out = Json::array();
        for (const auto& b : list) out.push_back({{"name", b.name}, {"eye", b.eye}, {"rect_px", {b.min_px.x, b.min_px.y, b.size_px.x, b.size_px.y}}});
        return out;
    };
    j["layout"] = {{"panels", boxes(s.layout.panels)}, {"views", boxes(s.layout.views)}, {"scene", boxes(s.layout.scene)}};
    j["results"] = s.results;
    j["result"] = s.result_json.empty() ? Json(nullptr) : Json::parse(s.result_json, nullptr, false);
    return assets::json_text(j);
}

Result<WindowState> parse_window_state(std::string_view text, const std::string& label) {
    // Depth first: nlohmann's parser recurses.
    if (const auto deep = assets::json_nesting_beyond(text, assets::max_json_depth))
        return make_error(ErrorCode::parse_error, label + ": line " + std::to_string(deep->line) + ", column " + std::to_string(deep->column) + ": nested deeper than " +
                                                      std::to_string(assets::max_json_depth));
    const Json j = Json::parse(text, nullptr, false);
    if (j.is_discarded() || !j.is_object()) return make_error(ErrorCode::parse_error, label + ": not a JSON object");
    Reader r;
    WindowState s;
    s.frame = r.get<std::uint64_t>(j, "frame");
    s.input_read_at_us = r.get<std::int64_t>(j, "input_read_at_us");
    s.sim_time_us = r.get<std::int64_t>(j, "sim_time_us");
    s.window_px = r.vector<2>(j, "window_px");
    s.cursor_px = r.vector<2>(j, "cursor_px");
    if (r.error.empty() && j.contains("pointer")) {
        const int active = r.get<int>(j["pointer"], "active_hand");
        if (r.error.empty() && (active < 0 || active > 1)) r.error = "field 'active_hand' should be 0 or 1";
        s.active_hand = static_cast<std::uint8_t>(active & 1);
        s.px_per_m = r.vector<2>(j["pointer"], "px_per_m");
    }
    const auto hands = r.get<Json>(j, "hands");
    if (r.error.empty() && (!hands.is_array() || hands.size() != 2)) r.error = "field 'hands' should hold two hands";
    for (std::size_t h = 0; r.error.empty() && h < 2; ++h) {
        s.hands[h].holding = r.get<bool>(hands[h], "holding");
        s.hands[h].held_flower = r.get<std::int32_t>(hands[h], "held_flower", -1);
        s.hands[h].position_m = r.vector<3>(hands[h], "position_m");
        s.hands[h].device_m = r.vector<3>(hands[h], "device_m");
        // Written since the force the device got was reported; older states have none.
        if (r.error.empty() && hands[h].contains("force_sent_n")) {
            s.hands[h].force_asked_n = r.vector<3>(hands[h], "force_asked_n");
            s.hands[h].force_sent_n = r.vector<3>(hands[h], "force_sent_n");
            s.hands[h].pushes = r.get<bool>(hands[h], "force_pushes");
            s.hands[h].link = r.get<std::string>(hands[h], "link");
        }
    }
    const auto flowers = r.get<Json>(j, "flowers");
    if (r.error.empty() && !flowers.is_array()) r.error = "field 'flowers' should be an array";
    for (std::size_t i = 0; r.error.empty() && i < flowers.size(); ++i) {
        const Json& f = flowers[i];
        WindowState::Flower out;
        out.species = r.get<std::string>(f, "species");
        for (const auto& p : r.get<std::vector<std::vector<double>>>(f, "points_m")) {
            if (p.size() != 3) r.error = "a point of flower " + std::to_string(i) + " should have 3 numbers";
            else out.points_m.emplace_back(p[0], p[1], p[2]);
        }
        out.diameter_m = r.get<double>(f, "diameter_m");
        out.in_kenzan = r.get<bool>(f, "in_kenzan");
        out.fallen = r.get<bool>(f, "fallen");
        const int reason = r.get<int>(f, "fall_reason");
        out.fall_reason = reason >= 0 && reason <= 3 ? static_cast<components::FallReason>(reason) : components::FallReason::none;
        out.yield_holding_nm = r.get<double>(f, "yield_holding_nm");
        out.yield_gravity_nm = r.get<double>(f, "yield_gravity_nm");
        out.pins_engaged = r.get<std::uint32_t>(f, "pins_engaged");
        out.depth_m = r.get<double>(f, "depth_m");
        s.flowers.push_back(std::move(out));
    }
    if (r.error.empty() && j.contains("kenzan")) {
        s.kenzan_origin_m = r.vector<3>(j["kenzan"], "origin_m");
        s.kenzan_pin_height_m = r.get<double>(j["kenzan"], "pin_height_m");
    }
    if (r.error.empty() && j.contains("screen")) s.screen = r.get<std::string>(j, "screen");
    if (r.error.empty() && j.contains("display")) s.display = r.get<std::string>(j, "display");
    if (r.error.empty() && j.contains("buttons")) {
        const auto& buttons = j["buttons"];
        if (!buttons.is_array() || buttons.size() > 200) r.error = "field 'buttons' should be an array of at most 200";
        for (std::size_t i = 0; r.error.empty() && i < buttons.size(); ++i) {
            WindowState::Button b;
            b.label = r.get<std::string>(buttons[i], "label");
            b.min_px = r.vector<2>(buttons[i], "min_px");
            b.max_px = r.vector<2>(buttons[i], "max_px");
            s.buttons.push_back(std::move(b));
        }
    }
    if (r.error.empty() && j.contains("layout")) {
        const auto read = [&](const char* key, std::vector<WindowState::Box>& into) {
            const auto list = r.get<Json>(j["layout"], key);
            if (r.error.empty() && (!list.is_array() || list.size() > 1000)) r.error = std::string("field 'layout.") + key + "' should be an array of at most 1000";
            for (std::size_t i = 0; r.error.empty() && i < list.size(); ++i) {
                WindowState::Box b;
                b.name = r.get<std::string>(list[i], "name");
                b.eye = r.get<int>(list[i], "eye");
                const auto rect = r.vector<4>(list[i], "rect_px");
                b.min_px = {rect.x, rect.y};
                b.size_px = {rect.z, rect.w};
                if (r.error.empty() && (b.size_px.x < 0.0 || b.size_px.y < 0.0)) r.error = std::string("a box in 'layout.") + key + "' has a negative size";
                into.push_back(std::move(b));
            }
        };
        read("panels", s.layout.panels);
        read("views", s.layout.views);
        read("scene", s.layout.scene);
    }
    s.results = r.get<std::uint64_t>(j, "results");
    if (r.error.empty() && j.contains("result") && !j["result"].is_null()) s.result_json = assets::json_text(j["result"]);
    if (!r.error.empty()) return make_error(ErrorCode::parse_error, label + ": " + r.error);
    return s;
}

std::optional<std::string> panel_over_scene(const WindowState& s) {
    const auto eye_words = [](int eye) { return eye < 0 ? " (left eye)" : eye > 0 ? " (right eye)" : ""; };
    for (const auto& p : s.layout.panels) {
        for (const auto* list : {&s.layout.views, &s.layout.scene}) {
            for (const auto& b : *list) {
                // Half a pixel of touching edges is not covering.
                const glm::dvec2 lo = glm::max(p.min_px, b.min_px), hi = glm::min(p.min_px + p.size_px, b.min_px + b.size_px);
                const glm::dvec2 over = hi - lo;
                if (over.x <= 0.5 || over.y <= 0.5) continue;
                char text[64];
                std::snprintf(text, sizeof text, " by %.0fx%.0f px", over.x, over.y);
                return "'" + p.name + "'" + eye_words(p.eye) + " covers '" + b.name + "'" + eye_words(b.eye) + text;
            }
        }
    }
    return std::nullopt;
}

Result<void> write_window_state(const std::string& path, const WindowState& state) { return assets::write_file_atomically(path, window_state_json(state)); }

} // namespace ikebana::game
