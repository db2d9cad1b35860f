#include "engine/devices/scripted_device.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <iterator>

#include "engine/assets/csv_table.hpp"
#include "engine/assets/files.hpp"
#include "engine/assets/json_checker.hpp"

namespace ikebana::devices {

namespace {
constexpr const char* header = "time_s,x_m,y_m,z_m,rx_rad,ry_rad,rz_rad,buttons";
}

Result<std::vector<Keyframe>> parse_trajectory(std::string_view text, const std::string& label) {
    std::vector<Keyframe> keys;
    bool seen_header = false;
    std::size_t line_no = 0;
    // Lines as spreadsheets write them (any ending, a byte-order mark dropped), as every CSV here.
    for (const auto& [line, ending] : assets::split_lines(text)) {
        ++line_no;
        if (line.empty() || line.front() == '#') continue;
        auto where = [&](std::size_t column) { return label + ":" + std::to_string(line_no) + ":" + std::to_string(column) + ": "; };
        if (!seen_header) {
            if (line != header) return make_error(ErrorCode::parse_error, where(1) + "expected the header '" + std::string(header) + "'");
            seen_header = true;
            continue;
        }
        // A row wider than the header is refused before it is split (a row of millions of commas
        // once took gigabytes as cells before its width was checked).
        if (const auto commas = static_cast<std::size_t>(std::count(line.begin(), line.end(), ',')); commas != 7)
            return make_error(ErrorCode::parse_error, where(1) + "expected 8 fields, found " + std::to_string(commas + 1));
        // Split into cells, remembering where each starts (for the column in messages).
        std::vector<std::pair<std::string_view, std::size_t>> cells;
        for (std::size_t pos = 0;;) {
            const std::size_t comma = line.find(',', pos);
            cells.emplace_back(line.substr(pos, comma == std::string_view::npos ? std::string_view::npos : comma - pos), pos + 1);
            if (comma == std::string_view::npos) break;
            pos = comma + 1;
        }
        if (cells.size() != 8) return make_error(ErrorCode::parse_error, where(1) + "expected 8 fields, found " + std::to_string(cells.size()));
        double fields[8] = {};
        for (std::size_t f = 0; f < 8; ++f) {
            const auto [cell, column] = cells[f];
            const auto [ptr, ec] = std::from_chars(cell.data(), cell.data() + cell.size(), fields[f]);
            if (cell.empty() || ec != std::errc{} || ptr != cell.data() + cell.size() || !std::isfinite(fields[f])) {
                return make_error(ErrorCode::parse_error, where(column) + "'" + std::string(cell) + "' is not a finite number");
            }
        }
        const std::size_t column = cells[7].second;
        if (fields[7] < 0 || fields[7] > 4294967295.0 || std::floor(fields[7]) != fields[7]) {
            return make_error(ErrorCode::parse_error, where(column) + "buttons must be a whole number bitmask");
        }
        if (std::abs(fields[0]) > max_trajectory_time_s) {
            return make_error(ErrorCode::parse_error, where(cells[0].second) + "time beyond the 1e9 s a trajectory may span");
        }
        for (std::size_t f = 1; f <= 3; ++f) {
            if (std::abs(fields[f]) > max_trajectory_reach_m) {
                return make_error(ErrorCode::parse_error, where(cells[f].second) + "a position beyond the 10 m any device reaches");
            }
        }
        for (std::size_t f = 4; f <= 6; ++f) {
            if (std::abs(fields[f]) > max_trajectory_rotation_rad) {
                return make_error(ErrorCode::parse_error, where(cells[f].second) + "a rotation beyond 1000 rad");
            }
        }
        if (!keys.empty() && !(fields[0] > keys.back().time_s)) {
            return make_error(ErrorCode::parse_error, where(1) + "time must increase (previous " + std::to_string(keys.back().time_s) + " s)");
        }
        keys.push_back({fields[0], {fields[1], fields[2], fields[3]}, {fields[4], fields[5], fields[6]}, static_cast<std::uint32_t>(fields[7])});
    }
    if (!seen_header) return make_error(ErrorCode::parse_error, label + ": empty; expected the header '" + std::string(header) + "'");
    if (keys.empty()) return make_error(ErrorCode::parse_error, label + ": no samples after the header");
    return keys;
}

Result<std::vector<Keyframe>> load_trajectory(const std::filesystem::path& path, std::uintmax_t max_bytes) {
    auto text = assets::read_text_file(path, max_bytes);
    if (!text) return std::move(text).error();
    return parse_trajectory(*text, path.string());
}

ScriptedDevice::ScriptedDevice(std::vector<Keyframe> keys, Mode mode, std::string name) : keys_(std::move(keys)), mode_(mode) {
    caps_.name = std::move(name);
    caps_.has_force_output = false;
    caps_.on_timeline = true;
    caps_.reports_position = true;
    caps_.workspace_half_extent_m = glm::dvec3{0.2};
}

Result<DeviceSample> ScriptedDevice::poll(std::int64_t now_us) {
    // The spans are in time order: the last one starting at or before now is the only one to look at.
    const auto span = std::upper_bound(away_.begin(), away_.end(), now_us, [](std::int64_t t, const auto& a) { return t < a.first; });
    if (span != away_.begin() && now_us < std::prev(span)->second) return make_error(ErrorCode::device_error, caps_.name + ": away here in the recording");
    DeviceSample s;
    s.time_us = now_us;
    if (keys_.empty()) return s;
    const double t = static_cast<double>(now_us) * 1e-6;
    const auto after = std::upper_bound(keys_.begin(), keys_.end(), t, [](double v, const Keyframe& k) { return v < k.time_s; });
    if (after == keys_.begin()) {
        s.position = keys_.front().position_m;
        s.rotation = keys_.front().rotation_rad;
        s.buttons = keys_.front().buttons;
        return s;
    }
    const Keyframe& a = *(after - 1);
    if (mode_ == Mode::replay || after == keys_.end()) {
        s.position = a.position_m;
        s.rotation = a.rotation_rad;
        s.buttons = a.buttons;
        return s;
    }
    const Keyframe& b = *after;
    const double u = (t - a.time_s) / (b.time_s - a.time_s);
    s.position = a.position_m + u * (b.position_m - a.position_m);
    s.rotation = a.rotation_rad + u * (b.rotation_rad - a.rotation_rad);
    s.buttons = a.buttons; // buttons change at keyframes, never half-way
    return s;
}

Result<void> ScriptedDevice::send_force(glm::dvec3 force_n) {
    last_force_ = force_n;
    return {};
}

DeviceRecorder::DeviceRecorder(std::ostream& out, AsyncLineWriter::WhenFull when_full) : writer_(out, when_full) {
    (void)writer_.write(std::string(header) + "\n");
}

void DeviceRecorder::record(const DeviceSample& s) {
    // Bit for bit (0.0 and -0.0 compare equal, and a replay must read what was read).
    const bool same = wrote_ && std::memcmp(&s.position, &last_.position, sizeof s.position) == 0 &&
                      std::memcmp(&s.rotation, &last_.rotation, sizeof s.rotation) == 0 && s.buttons == last_.buttons;
    if (same) return;
    wrote_ = true;
    last_ = s;
    char line[AsyncLineWriter::max_line_bytes];
    const int n = std::snprintf(line, sizeof line, "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%u\n", static_cast<double>(s.time_us) * 1e-6,
                                s.position.x, s.position.y, s.position.z, s.rotation.x, s.rotation.y, s.rotation.z, s.buttons);
    (void)writer_.write(std::string_view(line, static_cast<std::size_t>(std::clamp(n, 0, static_cast<int>(sizeof line) - 1))));
}

} // namespace ikebana::devices
