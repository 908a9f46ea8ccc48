#include "core/image/QuiltLayout.h"

#include <cmath>
#include <cstdio>

#include "core/base/Error.h"

namespace hvx::core {

void QuiltLayout::tileOrigin(int view, int& x, int& y) const {
    const int col = view % columns, rowFromBottom = view / columns;
    x = col * tileWidth;
    y = (rows - 1 - rowFromBottom) * tileHeight;
}

RenderImage QuiltLayout::assemble(const std::vector<RenderImage>& views) const {
    if (int(views.size()) != columns * rows)
        throw Error("a " + std::to_string(columns) + "x" + std::to_string(rows) + " quilt needs " +
                    std::to_string(columns * rows) + " views, not " + std::to_string(views.size()));
    RenderImage q;
    q.width = columns * tileWidth;
    q.height = rows * tileHeight;
    q.rgba.assign(std::size_t(q.width) * std::size_t(q.height), glm::vec4(0.0f));
    q.depth.assign(q.rgba.size(), INFINITY);
    for (int i = 0; i < int(views.size()); ++i) {
        const auto& v = views[std::size_t(i)];
        if (v.width != tileWidth || v.height != tileHeight) throw Error("a quilt view has the wrong size");
        int x0 = 0, y0 = 0;
        tileOrigin(i, x0, y0);
        for (int y = 0; y < tileHeight; ++y)
            for (int x = 0; x < tileWidth; ++x) {
                const std::size_t src = std::size_t(y) * std::size_t(tileWidth) + std::size_t(x);
                const std::size_t dst = std::size_t(y0 + y) * std::size_t(q.width) + std::size_t(x0 + x);
                q.rgba[dst] = v.rgba[src];
                q.depth[dst] = v.depth[src];
            }
    }
    return q;
}

std::string QuiltLayout::fileName(const std::string& base) const {
    std::string stem = base;
    if (stem.size() > 4 && stem.compare(stem.size() - 4, 4, ".png") == 0) stem.resize(stem.size() - 4);
    char a[32];
    std::snprintf(a, sizeof a, "%.4f", aspect);
    std::string aspectText = a;  // trailing zeros trimmed: 0.7500 -> 0.75, 1.0000 -> 1
    while (aspectText.back() == '0') aspectText.pop_back();
    if (aspectText.back() == '.') aspectText.pop_back();
    return stem + "_qs" + std::to_string(columns) + "x" + std::to_string(rows) + "a" + aspectText + ".png";
}

}  // namespace hvx::core
