#pragma once
// Running the beamtrace command from a test: exit code and everything it printed. The test target
// defines BEAMTRACE_CLI as the path of the built command (see tests/support/CMakeLists.txt).
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <string>

namespace beamtrace::test {

struct CommandResult {
    int exit_code;
    std::string output;  // stdout and stderr
};

inline CommandResult run_command(const std::string& args) {
    const std::string cmd = std::string(BEAMTRACE_CLI) + " " + args + " 2>&1";
    FILE* pipe = popen(cmd.c_str(), "r");
    if (!pipe) return {-1, "popen failed"};
    std::string out;
    std::array<char, 4096> buf;
    while (std::fgets(buf.data(), int(buf.size()), pipe)) out += buf.data();
    const int status = pclose(pipe);
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

// A folder of this test process under the system's temporary directory.
inline std::filesystem::path temp_dir(const std::string& tag) {
    const std::filesystem::path dir =
        std::filesystem::temp_directory_path() / ("beamtrace_" + tag + "_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    return dir;
}

}  // namespace beamtrace::test
