// Running gnuplot on a generated script.
#include "report/plot.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>

#include "beamtrace/error.hpp"

extern char** environ;

namespace beamtrace::report {

namespace fs = std::filesystem;

namespace {

// A gnuplot single-quoted string: no escapes inside, a quote is written twice.
std::string quoted(const std::string& s) {
    std::string out = "'";
    for (char c : s) {
        out += c;
        if (c == '\'') out += '\'';
    }
    return out + "'";
}

void write_file(const fs::path& path, const std::string& contents, const std::string& png) {
    std::ofstream f(path, std::ios::binary | std::ios::trunc);
    f << contents;
    f.close();
    if (!f) throw Error("plot '" + png + "': cannot write '" + path.string() + "'");
}

std::string read_log(const fs::path& path) {
    std::ifstream f(path, std::ios::binary);
    std::stringstream ss;
    ss << f.rdbuf();
    std::string s = ss.str();
    constexpr std::size_t kMax = 2000;
    if (s.size() > kMax) s = "..." + s.substr(s.size() - kMax);
    while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
    return s.empty() ? "(no output)" : s;
}

// Runs `gnuplot script` with stdout and stderr going to log; returns the wait status.
int run_gnuplot(const fs::path& script, const fs::path& log, const std::string& png) {
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&actions, 1, 2);
    std::string program = "gnuplot", script_arg = script.string();
    char* argv[] = {program.data(), script_arg.data(), nullptr};
    pid_t pid = 0;
    const int rc = posix_spawnp(&pid, "gnuplot", &actions, nullptr, argv, environ);
    posix_spawn_file_actions_destroy(&actions);
    if (rc != 0) {
        if (rc == ENOENT) throw Error("plot '" + png + "': gnuplot is not installed (not found on PATH)");
        throw Error("plot '" + png + "': cannot start gnuplot: " + std::strerror(rc));
    }
    int status = 0;
    while (waitpid(pid, &status, 0) < 0) {
        if (errno != EINTR) throw Error("plot '" + png + "': waiting for gnuplot failed: " + std::strerror(errno));
    }
    return status;
}

}  // namespace

bool gnuplot_available() {
    const char* path = std::getenv("PATH");
    if (path == nullptr) return false;
    std::stringstream dirs(path);
    std::string dir;
    while (std::getline(dirs, dir, ':')) {
        const fs::path candidate = (dir.empty() ? fs::path(".") : fs::path(dir)) / "gnuplot";
        std::error_code ec;
        if (fs::is_regular_file(candidate, ec) && access(candidate.c_str(), X_OK) == 0) return true;
    }
    return false;
}

void plot_with_gnuplot(const std::string& png_path, const std::string& body,
                       const std::vector<std::pair<std::string, std::string>>& data_files) {
    if (png_path.empty()) throw Error("plot: empty output path");
    for (const auto& [name, contents] : data_files) {
        if (name.empty() || name == "." || name == ".." || name.find('/') != std::string::npos || name == "plot.gp" ||
            name == "gnuplot.log")
            throw Error("plot '" + png_path + "': data file name '" + name +
                        "' must be a plain file name (no '/', not plot.gp or gnuplot.log)");
    }
    std::error_code ec;
    const fs::path png = fs::absolute(png_path, ec);
    if (ec) throw Error("plot '" + png_path + "': " + ec.message());
    const fs::path folder = png.parent_path() / (png.stem().string() + ".plot");
    fs::create_directories(folder, ec);
    if (ec) throw Error("plot '" + png_path + "': cannot create '" + folder.string() + "': " + ec.message());

    for (const auto& [name, contents] : data_files) write_file(folder / name, contents, png_path);
    const std::string script =
        "if (strstrt(GPVAL_TERMINALS, \"pngcairo\") > 0) { set terminal pngcairo size 1024,640 } "
        "else { set terminal png size 1024,640 }\n"
        "set output " +
        quoted(png.string()) +
        "\n"
        "cd " +
        quoted(folder.string()) + "\n" + body + "\nunset output\n";
    const fs::path script_path = folder / "plot.gp";
    write_file(script_path, script, png_path);

    fs::remove(png, ec);  // so that a stale PNG cannot pass for a new one
    const fs::path log = folder / "gnuplot.log";
    const int status = run_gnuplot(script_path, log, png_path);
    const bool ok = WIFEXITED(status) && WEXITSTATUS(status) == 0;
    if (!ok) fs::remove(png, ec);  // gnuplot opens the output before it fails: drop the partial file
    if (WIFSIGNALED(status))
        throw Error("plot '" + png_path + "': gnuplot was killed by signal " + std::to_string(WTERMSIG(status)) +
                    "; its output: " + read_log(log));
    if (!ok)
        throw Error("plot '" + png_path + "': gnuplot failed (exit status " + std::to_string(WEXITSTATUS(status)) +
                    ") running '" + script_path.string() + "': " + read_log(log));
    if (!fs::is_regular_file(png, ec) || fs::file_size(png, ec) == 0)
        throw Error("plot '" + png_path + "': gnuplot exited normally but wrote no PNG; its output: " + read_log(log));
}

}  // namespace beamtrace::report
