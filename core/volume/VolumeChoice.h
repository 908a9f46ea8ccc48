#pragma once
#include <cstdint>
#include <string>

#include "core/base/Error.h"

namespace hvx::core {

/// One volume picked from a file that may hold several (a 4-D NIfTI or NRRD): the refusal when
/// it does not exist and the sentence every multi-volume reader shows, worded once.
struct VolumeChoice {
    std::string path;
    std::uint32_t volumes = 1;  ///< how many the file holds
    std::uint32_t volume = 0;   ///< the one read, 0-based

    /// Why `volume` cannot be read ("PATH: holds N volumes; there is no volume V"), or "".
    std::string refusal() const {
        if (volume < volumes) return {};
        return path + ": holds " + std::to_string(volumes) + (volumes == 1 ? " volume" : " volumes") +
               "; there is no volume " + std::to_string(volume + 1);
    }
    /// Throws core::Error with refusal() when `volume` is past the file's last volume.
    void check() const {
        if (const std::string r = refusal(); !r.empty()) throw Error(r);
    }
    /// "PATH: a 4D file of N volumes; this is volume V" (1-based), or "" for a one-volume file.
    std::string note() const {
        if (volumes <= 1) return {};
        return path + ": a 4D file of " + std::to_string(volumes) + " volumes; this is volume " +
               std::to_string(volume + 1);
    }
};

}  // namespace hvx::core
