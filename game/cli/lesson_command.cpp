#include "game/cli/lesson_command.hpp"

#include <charconv>
#include <chrono>
#include <csignal>
#include <cstring>
#include <cinttypes>
#include <algorithm>
#include <cstdio>
#include <iostream>
#include <optional>
#include <ctime>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "engine/assets/json_checker.hpp"
#include "engine/assets/files.hpp"
#include "game/asset_paths.hpp"
#include "game/kenzan/kenzan_layout.hpp"
#include "game/training/form_score.hpp"
#include "game/lesson/lesson.hpp"
#include "game/session/lesson_demo.hpp"
#include "game/session/lesson_session.hpp"
#include "game/world/lesson_scene.hpp"
#include "game/progress/progress_db.hpp"
#include "game/scene/scene.hpp"

namespace ikebana::game {

namespace {
std::string roles_of(const LessonDef& l) {
    std::string roles;
    for (const auto& m : l.stems) roles += (roles.empty() ? "" : ", ") + m.role;
    return l.scoring == "sample" ? "against " + l.scene + "'s sample" : roles;
}

} // namespace

// What score and demo share: the output checked before any work, the lesson loaded; then the result
// said on the terminal and, with --json, written (or only printed, with --json -).
std::optional<LessonDef> lesson_for(const std::string& who, const std::string& lesson_name, const std::string& json_out) {
    if (!json_out.empty() && json_out != "-") {
        if (auto ok = assets::check_output_path(json_out); !ok) {
            std::cerr << who << "--json: " << ok.error().message << "\n";
            return std::nullopt;
        }
    }
    auto lesson = load_lesson(lesson_name);
    if (!lesson) {
        std::cerr << who << lesson.error().message << "\n";
        return std::nullopt;
    }
    return std::move(lesson).value();
}

int report(const std::string& who, const FormScore& result, const std::string& json_out, const std::vector<std::string>& before) {
    if (json_out == "-") {
        std::printf("%s", result.json().c_str());
        return 0;
    }
    for (const auto& line : before) std::printf("%s\n", line.c_str());
    for (const auto& line : result.lines()) std::printf("%s\n", line.c_str());
    if (!json_out.empty()) {
        if (auto w = assets::write_text_file(json_out, result.json()); !w) {
            std::cerr << who << w.error().message << "\n";
            return 2;
        }
        std::printf("every criterion, tip and the arrangement in %s\n", json_out.c_str());
    }
    return 0;
}

int list_lessons(bool json) {
    auto lessons = load_shipped_lessons();
    if (!lessons) {
        std::cerr << "ikebana lesson list: " << lessons.error().message << "\n";
        return 2;
    }
    if (json) {
        nlohmann::json out = nlohmann::json::array();
        for (const auto& l : *lessons) {
            nlohmann::json roles = nlohmann::json::array();
            for (const auto& m : l.stems) roles.push_back(m.role);
            out.push_back({{"id", l.id}, {"title", l.title}, {"school", l.school}, {"scoring", l.scoring}, {"roles", roles},
                           {"file", std::filesystem::relative(l.file, asset_dir()).string()}});
        }
        std::printf("%s\n", assets::json_text(out, 1).c_str());
        return 0;
    }
    for (const auto& l : *lessons) std::printf("%-26s %-9s %s (%s)\n", l.id.c_str(), l.school.c_str(), l.title.c_str(), roles_of(l).c_str());
    return 0;
}

int check_lesson_files(const std::vector<std::string>& files) {
    int bad = 0;
    for (const auto& file : files) {
        const auto lesson = load_lesson_file(file);
        if (!lesson) {
            ++bad;
            std::cerr << lesson.error().message << "\n";
            continue;
        }
        // `lesson demo ID` and the start screen find a lesson by its id, as lessons/<id>.json.
        if (const std::string stem = std::filesystem::path(file).stem().string(); lesson->id != stem) {
            ++bad;
            std::cerr << std::filesystem::path(file).filename().string() << ": /id: \"" << lesson->id << "\" is not the file's name (" << stem
                      << "): a lesson is found by its id, as lessons/<id>.json; make them agree\n";
            continue;
        }
        std::printf("%s: ok (%s: %s; %zu rule(s))\n", file.c_str(), lesson->id.c_str(), roles_of(*lesson).c_str(), lesson->rules.size());
    }
    if (bad > 0) std::cerr << bad << " of " << files.size() << " lesson file(s) have problems\n";
    return bad > 0 ? 1 : 0;
}

int score_lesson(const std::string& lesson_name, const std::string& arrangement_file, const std::string& json_out) {
    const std::string who = "ikebana lesson score: ";
    const auto lesson = lesson_for(who, lesson_name, json_out);
    if (!lesson) return 2;
    const auto arrangement = load_arrangement(arrangement_file);
    if (!arrangement) {
        std::cerr << who << arrangement.error().message << "\n";
        return 2;
    }
    FormScore result;
    if (lesson->scoring == "sample") {
        const auto file = named_from(lesson->file, lesson->scene);
        const auto scene = file ? load_scene(*file) : Result<SceneDef>(file.error());
        if (!scene) {
            std::cerr << who << scene.error().message << "\n";
            return 2;
        }
        result = score_sample(*lesson, *arrangement, scene->sample);
    } else {
        const auto footprint = footprint_of(*lesson);
        if (!footprint) {
            std::cerr << who << footprint.error().message << "\n";
            return 2;
        }
        auto scored = score_form(*lesson, *arrangement, *footprint, std::filesystem::path(arrangement_file).filename().string());
        if (!scored) {
            std::cerr << who << scored.error().message << "\n";
            return 2;
        }
        result = std::move(scored).value();
    }
    return report(who, result, json_out, {});
}

int print_model(const std::string& lesson_name) {
    const auto lesson = load_lesson(lesson_name);
    if (!lesson) {
        std::cerr << "ikebana lesson model: " << lesson.error().message << "\n";
        return 2;
    }
    if (lesson->scoring != "form") {
        std::cerr << "ikebana lesson model: " << lesson->id << " copies its scene's sample (" << lesson->scene << "); it has no form to model\n";
        return 2;
    }
    const auto footprint = footprint_of(*lesson);
    if (!footprint) {
        std::cerr << "ikebana lesson model: " << footprint.error().message << "\n";
        return 2;
    }
    std::printf("%s", arrangement_json(model_arrangement(*lesson, *footprint)).c_str());
    return 0;
}

struct DemoArgs {
    std::string lesson, json_out;
    bool mouse = false;
    bool window = false;
    std::string xdotool, record;
    std::vector<std::string> tilts; // role=degrees
    std::string db;                 // the progress database (empty: the default one)
    bool no_history = false;
    bool main_stems_only = false;
};

// A demonstration stopped by a signal (Ctrl-C, a timeout) says which step it was at and how long it
// had run, and ends the window it drove; the handler only writes what the progress callback prepared.
struct StoppedDemo {
    char line[400] = "ikebana lesson demo: stopped before its first step\n";
    volatile sig_atomic_t length = 0;
    volatile pid_t window_pid = 0;
    std::chrono::steady_clock::time_point started;
};
StoppedDemo stopped_demo;

void remember_step(std::size_t done, std::size_t of, const std::string& step) {
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - stopped_demo.started).count();
    stopped_demo.length = 0;
    const int n = std::snprintf(stopped_demo.line, sizeof stopped_demo.line, "\nikebana lesson demo: stopped at step %zu of %zu, %.0f s in: %s\n", done, of, s,
                                step.c_str());
    stopped_demo.length = n < 0 ? 0 : std::min<int>(n, static_cast<int>(sizeof stopped_demo.line) - 1);
}

extern "C" void say_where_it_stopped(int signal_number) {
    const sig_atomic_t length = stopped_demo.length;
    const char* line = stopped_demo.line;
    const auto size = length > 0 ? static_cast<std::size_t>(length) : std::strlen(line);
    (void)!::write(STDERR_FILENO, line, size);
    if (stopped_demo.window_pid > 0) ::kill(stopped_demo.window_pid, SIGTERM);
    std::signal(signal_number, SIG_DFL);
    std::raise(signal_number);
}

// A demonstration goes into the progress database beside the trainees' sessions, marked as one.
int store_demonstration(const std::string& who, const DemoArgs& args, const LessonDef& lesson, const DemoResult& demo, std::int64_t started_unix_s) {
    const std::filesystem::path path = args.db.empty() ? default_progress_path() : std::filesystem::path(args.db);
    auto db = ProgressDb::open(path);
    if (!db) {
        std::cerr << who << "the demonstration was not stored: " << db.error().message << "\n";
        return 1;
    }
    SessionRecord s;
    s.lesson = lesson.id;
    s.trainee = "teacher";
    s.kind = "demonstration";
    s.started_unix_s = started_unix_s;
    s.duration_s = demo.simulated_s;
    s.result = demo.score;
    s.flowers = demo.flowers;
    if (!args.record.empty()) s.recording = std::filesystem::absolute(args.record).lexically_normal().string();
    if (auto saved = db->save(s); !saved) {
        std::cerr << who << "the demonstration was not stored: " << saved.error().message << "\n";
        return 1;
    }
    if (args.json_out != "-") std::printf("stored as session %lld in %s (ikebana history)\n", static_cast<long long>(s.id), path.string().c_str());
    return 0;
}

int demo_lesson(const DemoArgs& args) {
    const std::string who = "ikebana lesson demo: ";
    const auto lesson = lesson_for(who, args.lesson, args.json_out);
    if (!lesson) return 2;
    DemoOptions options;
    options.through_mouse = args.mouse || !args.xdotool.empty();
    options.xdotool_script = args.xdotool;
    if (!args.xdotool.empty()) {
        if (auto ok = assets::check_output_path(args.xdotool); !ok) {
            std::cerr << who << "--xdotool: " << ok.error().message << "\n";
            return 2;
        }
    }
    // The database is looked at before a minute is spent demonstrating: a FIFO or a device there is
    // refused now, not after (the window stores through the app, which opens it at its start).
    if (!args.no_history && !args.window) {
        if (auto ok = check_progress_path(args.db.empty() ? default_progress_path() : std::filesystem::path(args.db)); !ok) {
            std::cerr << who << "--db: " << ok.error().message << "\n";
            return 2;
        }
    }
    options.main_stems_only = args.main_stems_only;
    for (const auto& t : args.tilts) {
        const auto eq = t.find('=');
        const auto role = t.substr(0, eq);
        const bool known = std::any_of(lesson->stems.begin(), lesson->stems.end(), [&](const MainStemDef& m) { return m.role == role; });
        double deg = -1.0; // decimal only (strtod reads "0x1E" too)
        const char* text = eq == std::string::npos ? t.c_str() + t.size() : t.c_str() + eq + 1;
        const auto [end, ec] = std::from_chars(text, t.c_str() + t.size(), deg);
        if (eq == std::string::npos || !known || ec != std::errc{} || end != t.c_str() + t.size() || !(deg >= 0.0 && deg <= 90.0)) {
            std::cerr << who << "--tilt: '" << t << "': expected ROLE=DEGREES with a role of " << lesson->id << " and 0-90 degrees\n";
            return 2;
        }
        options.tilt_deg[role] = deg;
    }
    const bool tty = isatty(fileno(stderr)) != 0;
    // Each step as it starts: on a terminal in one line; in the window (minutes long) also into a pipe
    // or log, a line a step. The step is kept for a signal that stops the command, which says where.
    const bool lines = !tty && args.window;
    options.progress = [tty, lines](std::size_t done, std::size_t planned, const std::string& step) {
        const std::size_t of = std::max(done, planned); // a stem taken again adds steps to the plan
        remember_step(done, of, step);
        if (tty) std::fprintf(stderr, "\r\033[K[%zu/%zu] %s", done, of, step.c_str());
        else if (lines) std::fprintf(stderr, "[%zu/%zu] %s\n", done, of, step.c_str());
    };
    options.window_started = [](int pid) { stopped_demo.window_pid = pid; };
    stopped_demo.started = std::chrono::steady_clock::now();
    std::signal(SIGINT, say_where_it_stopped);
    std::signal(SIGTERM, say_where_it_stopped);
    options.record_dir = args.record;
    if (args.window && !args.record.empty()) {
        std::cerr << who << "--record records the headless demonstration; the window records its own session beside the progress database (`ikebana history --json` says where)\n";
        return 2;
    }
    if (args.window && (args.mouse || !args.xdotool.empty())) {
        std::cerr << who << "--window works the window with the X pointer itself; --mouse and --xdotool are for the headless demonstration\n";
        return 2;
    }
    // The window stores its own session (it is the one that scores); it is told it is a demonstration.
    options.window_progress_db = args.no_history ? "" : (args.db.empty() ? default_progress_path().string() : args.db);
    const auto started_unix_s = static_cast<std::int64_t>(std::time(nullptr));
    const auto demo = args.window ? run_lesson_demo_in_window(*lesson, options) : run_lesson_demo(*lesson, options);
    if (tty) std::fprintf(stderr, "\r\033[K");
    if (!demo) {
        std::cerr << who << demo.error().message << "\n";
        return 2;
    }
    char heading[200];
    std::snprintf(heading, sizeof heading, "%s, demonstrated in %.1f s of simulated time through %s: %zu steps", lesson->title.c_str(), demo->simulated_s,
                  args.window ? "the X pointer in the window" : args.mouse ? "the mouse" : "the hands' devices", demo->steps.size());
    std::vector<std::string> before{heading};
    for (const auto& step : demo->steps) {
        char line[300];
        std::snprintf(line, sizeof line, "  %5.1f s  %s", step.at_s, step.what.c_str());
        before.emplace_back(line);
    }
    int code = report(who, demo->score, args.json_out, before);
    if (code == 0 && !args.window && !args.no_history) code = store_demonstration(who, args, *lesson, *demo, started_unix_s);
    if (code == 0 && !args.record.empty() && args.json_out != "-")
        std::printf("the session is on record in %s (replay: ikebana lesson replay %s)\n", args.record.c_str(), args.record.c_str());
    return code;
}

int replay_session(const std::string& who, const std::string& folder, const std::string& json_out) {
    if (!json_out.empty() && json_out != "-") {
        if (auto ok = assets::check_output_path(json_out); !ok) {
            std::cerr << who << "--json: " << ok.error().message << "\n";
            return 2;
        }
    }
    const bool tty = isatty(fileno(stderr)) != 0;
    const auto replayed = replay_lesson_session(folder, [tty](double done, double of) {
        if (tty) std::fprintf(stderr, "\r\033[Kreplaying: %.0f of %.0f s simulated", done, of);
    });
    if (tty) std::fprintf(stderr, "\r\033[K");
    if (!replayed) {
        std::cerr << who << replayed.error().message << "\n";
        return 2;
    }
    char heading[200];
    std::snprintf(heading, sizeof heading, "%s replayed: %.1f s of simulated time", replayed->kind.c_str(), replayed->seconds);
    const int code = report(who, replayed->score, json_out, {heading});
    if (code != 0) return code;
    const bool same_hash = replayed->state_hash == replayed->recorded_state_hash;
    const bool same_score = std::abs(replayed->score.score - replayed->recorded_score) < 1e-6;
    if (json_out != "-") {
        std::printf("state-hash: %016" PRIx64 " (%s)\n", replayed->state_hash, same_hash ? "as recorded" : "the recording ended elsewhere");
    }
    if (!same_hash || !same_score) {
        std::cerr << who << "the replay does not reach the recorded session: score " << replayed->score.score << " against " << replayed->recorded_score
                  << (same_hash ? "" : ", another final state");
        for (std::size_t i = 0; i < replayed->parted.size(); ++i) std::cerr << (i ? ", " : " (it parts in ") << replayed->parted[i] << (i + 1 == replayed->parted.size() ? ")" : "");
        std::cerr << "\n";
        return 1;
    }
    return 0;
}

void add_lesson_command(CLI::App& app, int& exit_code) {
    auto* lesson = app.add_subcommand("lesson", "The school forms a trainee practises (assets/lessons/*.json)");
    lesson->require_subcommand(1);
    auto json = std::make_shared<bool>(false);
    auto* list = lesson->add_subcommand("list", "The shipped lessons");
    list->add_flag("--json", *json, "As JSON");
    list->callback([json, &exit_code] { exit_code = list_lessons(*json); });

    auto files = std::make_shared<std::vector<std::string>>();
    auto* check = lesson->add_subcommand("check", "Validate lesson files; every problem is printed with its JSON path");
    check->add_option("files", *files, "Lesson files")->required()->check(CLI::ExistingFile);
    check->callback([files, &exit_code] { exit_code = check_lesson_files(*files); });

    auto model_of = std::make_shared<std::string>();
    auto* model = lesson->add_subcommand("model", "Print the form's model arrangement as JSON (what --arrangement accepts)");
    model->add_option("lesson", *model_of, "Lesson id or file")->required();
    model->callback([model_of, &exit_code] { exit_code = print_model(*model_of); });

    auto demo_args = std::make_shared<DemoArgs>();
    auto* demo = lesson->add_subcommand("demo", "The teacher's demonstration: a scripted trainee arranges the form through the hands, cuts and insertions a trainee uses");
    demo->add_option("lesson", demo_args->lesson, "Lesson id or file")->required();
    demo->add_option("--json", demo_args->json_out, "Also write the result (with the measured arrangement) as JSON here (- : only the JSON)");
    demo->add_flag("--mouse", demo_args->mouse, "Through the mouse and the lesson's keys as the window reads them, not a device");
    demo->add_option("--xdotool", demo_args->xdotool, "With --mouse: also write the session as an xdotool script, to replay against the window (ikebana --lesson LESSON)");
    demo->add_flag("--window", demo_args->window, "In the trainee window, worked from outside through the X pointer and keys (needs a display and xdotool); its result is the window's");
    demo->add_option("--record", demo_args->record, "Put the session on record in this folder (device samples, cuts, score, state hash), for `lesson replay`");
    demo->add_flag("--main-stems-only", demo_args->main_stems_only, "Place the main stems alone, no supporting stems (a shorter demonstration; the kenzan rule then fails)");
    demo->add_option("--tilt", demo_args->tilts, "ROLE=DEGREES: hold that role at another tilt (how a mistake scores); repeatable");
    demo->add_option("--db", demo_args->db, "The progress database the demonstration is stored in (default: $XDG_DATA_HOME/ikebana/progress.sqlite)");
    demo->add_flag("--no-history", demo_args->no_history, "Do not store the demonstration in the progress database");
    demo->callback([demo_args, &exit_code] { exit_code = demo_lesson(*demo_args); });

    auto replay_args = std::make_shared<std::pair<std::string, std::string>>();
    auto* replay = lesson->add_subcommand("replay", "Play a recorded lesson session back on the deterministic clock: the same score and final state hash, or an error");
    replay->add_option("folder", replay_args->first, "The folder `lesson demo --record` wrote")->required();
    replay->add_option("--json", replay_args->second, "Also write the result as JSON here (- : only the JSON)");
    replay->callback([replay_args, &exit_code] { exit_code = replay_session("ikebana lesson replay: ", replay_args->first, replay_args->second); });

    struct ScoreArgs {
        std::string lesson, arrangement, json;
    };
    auto args = std::make_shared<ScoreArgs>();
    auto* score = lesson->add_subcommand("score", "Score an arrangement described as data against a lesson, criterion by criterion");
    score->add_option("lesson", args->lesson, "Lesson id (see `lesson list`) or file")->required();
    score->add_option("--arrangement", args->arrangement, "The arrangement (JSON: {\"stems\": [...]}, or a result whose \"arrangement\" is one)")
        ->required()
        ->check(CLI::ExistingFile);
    score->add_option("--json", args->json, "Also write the whole result as JSON here (- : only the JSON, on standard output)");
    score->callback([args, &exit_code] { exit_code = score_lesson(args->lesson, args->arrangement, args->json); });
}

} // namespace ikebana::game
