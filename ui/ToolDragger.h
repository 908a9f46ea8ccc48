#pragma once
#include <QPoint>

#include <optional>

#include "core/appearance/ToolSet.h"
#include "core/camera/OrbitCamera.h"

namespace hvx::ui {

/// Direct manipulation of the illustrative tools in the 3D view. Ctrl+drag moves the probes in
/// the view plane (with Shift: along the view); with the clip plane alone, Ctrl+drag pushes the
/// plane along its normal (with Shift: tilts it about the view's axes); Ctrl+wheel scales the
/// probes. A Ctrl-press that does not move more than 3 pixels is a click (a pick), not a drag.
/// It only computes the changed tools; the view emits and redraws.
///
/// Threading: GUI thread (plain state, no Qt objects).
class ToolDragger {
public:
    /// A Ctrl/Alt left press at `pos` starts a tool gesture.
    void press(const QPoint& pos);
    bool active() const { return active_; }
    /// A mouse move during the gesture; the changed tools, or nothing while it is still a click
    /// or no tool can be dragged.
    std::optional<core::ToolSet> move(const QPoint& pos, const QPoint& delta, bool shift, const core::ToolSet& tools,
                                      const core::OrbitCamera& camera, int width, int height);
    /// Ends the gesture; true when it was a click (the mouse did not move).
    bool release();
    /// Ctrl+wheel: the probes scaled by 1.1 per wheel step, or nothing when no probe is on.
    static std::optional<core::ToolSet> scaled(const core::ToolSet& tools, double steps);

private:
    static core::ToolSet movedProbes(core::ToolSet tools, const QPoint& d, bool alongView,
                                     const core::OrbitCamera& camera, int width, int height);
    static core::ToolSet movedClipPlane(core::ToolSet tools, const QPoint& d, bool tilt,
                                        const core::OrbitCamera& camera, int height);

    bool active_ = false, moved_ = false;
    QPoint pressPos_;
};

}  // namespace hvx::ui
