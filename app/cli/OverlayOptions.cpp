#include "app/cli/OverlayOptions.h"

#include <cstdio>
#include <cstdlib>

#include "core/base/Error.h"
#include "core/volume/FramePairing.h"

namespace hvx::app {

std::pair<std::string, std::map<std::string, std::string>> overlaySpec(const std::string& text) {
    std::map<std::string, std::string> opts;
    const auto colon = text.rfind(':');
    if (colon == std::string::npos || text.find('=', colon) == std::string::npos) return {text, opts};
    std::string rest = text.substr(colon + 1);
    for (std::size_t at = 0; at <= rest.size();) {
        const auto comma = std::min(rest.find(',', at), rest.size());
        const std::string kv = rest.substr(at, comma - at);
        const auto eq = kv.find('=');
        if (eq == std::string::npos || (kv.substr(0, eq) != "lut" && kv.substr(0, eq) != "opacity" && kv.substr(0, eq) != "window"))
            throw core::Error("--overlay options are lut=NAME|FILE, opacity=0..1 and window=W/L (\"" + kv + "\" given)");
        opts[kv.substr(0, eq)] = kv.substr(eq + 1);
        at = comma + 1;
    }
    return {text.substr(0, colon), opts};
}

OverlayLook overlayLook(const std::map<std::string, std::string>& opts, const core::VolumeGeometry& g) {
    OverlayLook look{core::ColorMap::namedOrFile(opts.count("lut") ? opts.at("lut") : "hot"), core::DisplayWindow::initial(g),
                     0.5};
    if (opts.count("opacity")) {
        char* end = nullptr;
        const std::string& text = opts.at("opacity");
        look.opacity = std::strtod(text.c_str(), &end);
        if (text.empty() || *end || !(look.opacity >= 0 && look.opacity <= 1))
            throw core::Error("--overlay opacity must be 0 to 1 (\"" + text + "\" given)");
    }
    if (opts.count("window")) {
        double ww = 0, wl = 0;
        if (std::sscanf(opts.at("window").c_str(), "%lf/%lf", &ww, &wl) != 2 || !(ww > 0))
            throw core::Error("--overlay window=W/L needs a width above 0 and a level");
        look.window = {"", wl, ww};
    }
    return look;
}

void pairFrames(const core::VolumeGeometry& base, const std::string& baseName, const core::VolumeGeometry& partner,
                const std::string& partnerName, bool force) {
    const auto pairing = core::FramePairing::of(base, baseName, partner, partnerName);
    if (pairing.refused && !force) throw core::Error(pairing.sentence + " (--force-frame lays it over anyway)");
    if (!pairing.sentence.empty()) std::printf("note: %s%s\n", pairing.sentence.c_str(), pairing.refused ? " (forced)" : "");
}

}  // namespace hvx::app
