#include "oracle/embree_device.hpp"

#include "beamtrace/error.hpp"

namespace beamtrace::oracle {

const char* error_name(RTCError code) {
    switch (code) {
        case RTC_ERROR_NONE:
            return "no error";
        case RTC_ERROR_UNKNOWN:
            return "unknown error";
        case RTC_ERROR_INVALID_ARGUMENT:
            return "invalid argument";
        case RTC_ERROR_INVALID_OPERATION:
            return "invalid operation";
        case RTC_ERROR_OUT_OF_MEMORY:
            return "out of memory";
        case RTC_ERROR_UNSUPPORTED_CPU:
            return "unsupported CPU";
        case RTC_ERROR_CANCELLED:
            return "cancelled";
    }
    return "unrecognised error code";
}

EmbreeDevice::EmbreeDevice(std::string who, int threads) : who_(std::move(who)) {
    const std::string config = threads > 0 ? "verbose=0,threads=" + std::to_string(threads) : "verbose=0";
    device_ = rtcNewDevice(config.c_str());
    if (device_ == nullptr)
        throw Error(who_ + ": cannot create an Embree device: " + error_name(rtcGetDeviceError(nullptr)));
    rtcSetDeviceErrorFunction(device_, &EmbreeDevice::on_error, this);
    rtcSetDeviceMemoryMonitorFunction(device_, &EmbreeDevice::on_memory, this);
}

EmbreeDevice::~EmbreeDevice() {
    if (device_ != nullptr) rtcReleaseDevice(device_);
}

void EmbreeDevice::on_error(void* user, RTCError code, const char* text) {
    auto* self = static_cast<EmbreeDevice*>(user);
    std::lock_guard<std::mutex> lock(self->error_mutex_);
    if (self->first_error_.empty())
        self->first_error_ = std::string(error_name(code)) + (text != nullptr ? std::string(": ") + text : "");
}

bool EmbreeDevice::on_memory(void* user, ssize_t bytes, bool /*post*/) {
    static_cast<EmbreeDevice*>(user)->allocated_.fetch_add(bytes, std::memory_order_relaxed);
    return true;  // never veto an allocation
}

void EmbreeDevice::check(const char* step) {
    std::lock_guard<std::mutex> lock(error_mutex_);
    if (!first_error_.empty()) throw Error(who_ + ": " + step + " failed: " + first_error_);
}

std::size_t EmbreeDevice::bytes() const {
    const std::int64_t held = allocated_.load();
    return held > 0 ? static_cast<std::size_t>(held) : 0;
}

}  // namespace beamtrace::oracle
