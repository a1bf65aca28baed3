// The child process: fork, import, send the arrays through a pipe; the parent waits with a deadline.
#include "scenes/isolated_import.hpp"

#include <poll.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>

#include "beamtrace/error.hpp"
#include "scenes/assimp_import.hpp"

namespace beamtrace::scenes {

namespace {

constexpr std::uint8_t kArrays = 0, kError = 1;
constexpr int kDeadlineSeconds = 600;

bool write_all(int fd, const void* data, std::size_t n) {
    const char* p = static_cast<const char*>(data);
    while (n > 0) {
        const ssize_t w = ::write(fd, p, n);
        if (w < 0 && errno == EINTR) continue;
        if (w <= 0) return false;
        p += w;
        n -= std::size_t(w);
    }
    return true;
}

// Reads exactly n bytes before the deadline; false at the end of the pipe.
bool read_all(int fd, void* data, std::size_t n, std::chrono::steady_clock::time_point deadline, bool& late) {
    char* p = static_cast<char*>(data);
    while (n > 0) {
        const auto left =
            std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
        if (left.count() <= 0) {
            late = true;
            return false;
        }
        pollfd pfd{fd, POLLIN, 0};
        const int ready = ::poll(&pfd, 1, int(std::min<long long>(left.count(), 60000)));
        if (ready < 0 && errno == EINTR) continue;
        if (ready == 0) continue;
        if (ready < 0) return false;
        const ssize_t r = ::read(fd, p, n);
        if (r < 0 && errno == EINTR) continue;
        if (r <= 0) return false;
        p += r;
        n -= std::size_t(r);
    }
    return true;
}

void send_error(int fd, const std::string& what) {
    const std::uint64_t length = what.size();
    write_all(fd, &kError, 1);
    write_all(fd, &length, sizeof length);
    write_all(fd, what.data(), what.size());
}

[[noreturn]] void run_child(int fd, const std::string& path) {
    // An abort or a fault in Assimp must end this process with that signal, whatever handlers the
    // parent installed (sanitizers, fuzzers, applications).
    for (int sig : {SIGABRT, SIGSEGV, SIGBUS, SIGFPE, SIGILL}) std::signal(sig, SIG_DFL);
    try {
        const MeshArrays m = import_with_assimp(path);
        const std::uint32_t meshes = m.meshes;
        const std::uint64_t nv = m.vertices.size(), ni = m.indices.size(), no = m.mesh_of_triangle.size();
        const bool sent = write_all(fd, &kArrays, 1) && write_all(fd, &meshes, sizeof meshes) &&
                          write_all(fd, &nv, sizeof nv) && write_all(fd, &ni, sizeof ni) &&
                          write_all(fd, &no, sizeof no) && write_all(fd, m.vertices.data(), nv * sizeof(Float3)) &&
                          write_all(fd, m.indices.data(), ni * sizeof(std::uint32_t)) &&
                          write_all(fd, m.mesh_of_triangle.data(), no * sizeof(std::uint32_t));
        ::_exit(sent ? 0 : 3);
    } catch (const Error& e) {
        send_error(fd, e.what());
    } catch (const std::exception& e) {
        send_error(fd, "cannot read " + path + ": Assimp failed: " + e.what());
    } catch (...) {
        send_error(fd, "cannot read " + path + ": Assimp failed");
    }
    ::_exit(0);
}

std::string signal_name(int sig) {
    const char* name = ::strsignal(sig);
    return "signal " + std::to_string(sig) + (name != nullptr ? std::string(", ") + name : std::string());
}

}  // namespace

MeshArrays import_in_child_process(const std::string& path) {
    int fds[2];
    if (::pipe(fds) != 0) throw Error("cannot read " + path + ": cannot create a pipe: " + std::strerror(errno));
    std::fflush(nullptr);  // the child must not write out the parent's buffered output again
    const pid_t pid = ::fork();
    if (pid < 0) {
        const int e = errno;
        ::close(fds[0]);
        ::close(fds[1]);
        throw Error("cannot read " + path + ": cannot start the importer process: " + std::strerror(e));
    }
    if (pid == 0) {
        ::close(fds[0]);
        run_child(fds[1], path);
    }
    ::close(fds[1]);

    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(kDeadlineSeconds);
    bool late = false, complete = false;
    std::string error;
    MeshArrays m;
    std::uint8_t kind = 0;
    if (read_all(fds[0], &kind, 1, deadline, late)) {
        if (kind == kArrays) {
            std::uint32_t meshes = 0;
            std::uint64_t nv = 0, ni = 0, no = 0;
            if (read_all(fds[0], &meshes, sizeof meshes, deadline, late) &&
                read_all(fds[0], &nv, sizeof nv, deadline, late) && read_all(fds[0], &ni, sizeof ni, deadline, late) &&
                read_all(fds[0], &no, sizeof no, deadline, late) && no <= ni / 3) {
                m.meshes = meshes;
                m.vertices.resize(nv);
                m.indices.resize(ni);
                m.mesh_of_triangle.resize(no);
                complete = read_all(fds[0], m.vertices.data(), nv * sizeof(Float3), deadline, late) &&
                           read_all(fds[0], m.indices.data(), ni * sizeof(std::uint32_t), deadline, late) &&
                           read_all(fds[0], m.mesh_of_triangle.data(), no * sizeof(std::uint32_t), deadline, late);
            }
        } else if (kind == kError) {
            std::uint64_t length = 0;
            if (read_all(fds[0], &length, sizeof length, deadline, late) && length < (1u << 20)) {
                error.resize(length);
                complete = read_all(fds[0], error.data(), length, deadline, late);
            }
        }
    }
    ::close(fds[0]);
    if (late) ::kill(pid, SIGKILL);
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {}
    if (late)
        throw Error("cannot read " + path + ": the importer (Assimp) did not finish within " +
                    std::to_string(kDeadlineSeconds) + " s");
    if (WIFSIGNALED(status))
        throw Error("cannot read " + path + ": the importer (Assimp) crashed on it (" + signal_name(WTERMSIG(status)) +
                    "); the file is malformed");
    if (!complete || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
        throw Error("cannot read " + path + ": the importer (Assimp) stopped without an answer (exit code " +
                    std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) + ")");
    if (kind == kError) throw Error(error);
    return m;
}

}  // namespace beamtrace::scenes
