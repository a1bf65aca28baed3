#pragma once
// One Embree device with the callbacks every Embree user of the tools needs: the first error Embree
// reports is kept and thrown as beamtrace::Error by check(), and the bytes the device holds are
// counted by its memory monitor. For the oracle's sources only: it includes Embree's header.
#include <embree3/rtcore.h>

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <mutex>
#include <string>

namespace beamtrace::oracle {

class EmbreeDevice {
public:
    // `who` starts every error message ("embree oracle", "embree animation"). threads: the device's
    // worker threads (builds), 0 for Embree's default. Throws when Embree cannot make a device.
    explicit EmbreeDevice(std::string who, int threads = 0);
    ~EmbreeDevice();
    EmbreeDevice(const EmbreeDevice&) = delete;
    EmbreeDevice& operator=(const EmbreeDevice&) = delete;

    RTCDevice get() const { return device_; }
    // Throws the first error Embree reported (if any), naming `step`.
    void check(const char* step);
    // Bytes the device holds now (buffers, BVHs, builder leftovers).
    std::size_t bytes() const;

private:
    static void on_error(void* user, RTCError code, const char* text);
    static bool on_memory(void* user, ssize_t bytes, bool post);

    std::string who_;
    RTCDevice device_ = nullptr;
    std::atomic<std::int64_t> allocated_{0};  // the monitor may be called from build threads at once
    std::mutex error_mutex_;
    std::string first_error_;
};

// Embree's name of an error code ("invalid argument", ...).
const char* error_name(RTCError code);

}  // namespace beamtrace::oracle
