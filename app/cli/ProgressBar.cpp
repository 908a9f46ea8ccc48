#include "app/cli/ProgressBar.h"

#include <unistd.h>

#include <cstdio>

namespace hvx::app {

ProgressBar::ProgressBar(std::string label) : label_(std::move(label)), enabled_(::isatty(2) != 0) {}

ProgressBar::~ProgressBar() { finish(); }

core::JobContext::Observer ProgressBar::observer() {
    return [this](const core::JobProgress& p) { draw(p); };
}

void ProgressBar::draw(const core::JobProgress& p) {
    if (!enabled_) return;
    constexpr int width = 40;
    const int filled = int(p.fraction * width);
    std::string bar(std::size_t(filled), '#');
    bar.resize(width, '.');
    char eta[32] = "";
    if (p.etaSeconds >= 0) std::snprintf(eta, sizeof eta, " ETA %.0fs", p.etaSeconds);
    std::fprintf(stderr, "\r%s [%s] %5.1f%%%s   ", label_.c_str(), bar.c_str(), p.fraction * 100.0, eta);
    std::fflush(stderr);
    drawn_ = true;
}

void ProgressBar::finish() {
    if (drawn_) std::fprintf(stderr, "\n");
    drawn_ = false;
}

}  // namespace hvx::app
