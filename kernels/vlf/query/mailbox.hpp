#pragma once
// Mailboxing: no triangle is tested twice by one ray, although a triangle sits in every tile and
// every tile-BSP leaf it touches. One stamp per triangle and thread: the stamp of the current ray
// marks the triangles it has tested.
#include <algorithm>
#include <cstdint>
#include <vector>

namespace beamtrace::vlf {

class Mailbox {
public:
    // The calling thread's mailbox.
    static Mailbox& local() {
        thread_local Mailbox box;
        return box;
    }

    // Starts a ray over a field of `triangles` triangles.
    void begin(std::size_t triangles) {
        if (stamps_.size() < triangles) stamps_.resize(triangles, 0);
        if (++ray_ == 0) {  // the stamps wrapped around: forget every earlier ray
            std::fill(stamps_.begin(), stamps_.end(), 0u);
            ray_ = 1;
        }
    }
    // True if the current ray has tested `id` already; otherwise records that it does now.
    bool seen(std::uint32_t id) {
        std::uint32_t& s = stamps_[id];
        if (s == ray_) return true;
        s = ray_;
        return false;
    }

private:
    std::vector<std::uint32_t> stamps_;
    std::uint32_t ray_ = 0;
};

}  // namespace beamtrace::vlf
