#pragma once

namespace hvx::core {

/// Interaction quality (thesis §5.5: "lowering the sampling rate during interaction, by reducing
/// the pixel count and doubling the integration step-size"): while the camera moves, frames are
/// drawn at a reduced resolution and a larger step, sized from the measured cost of earlier frames
/// so that a frame fits the target time; the first frame after the camera stops is full quality.
///
/// Threading: frame thread only.
class InteractiveQuality {
public:
    struct Options {
        double targetFrameMs = 40.0;  ///< the frame time to hold while moving (25 Hz)
        double minResolution = 0.25;  ///< lowest resolution scale (per axis)
        double movingStepScale = 2.0; ///< step multiplier while moving
        /// While moving, each frame draws one quincunx sub-frame, a quarter of the rays, and
        /// the image is rebuilt from the last four (thesis §3.3, core::FrameReconstructor).
        bool subFrames = false;
    };
    /// What to draw: per-axis resolution scale and step scale.
    struct Level {
        double resolution = 1.0;
        double stepScale = 1.0;
        bool subFrame = false;  ///< draw one quincunx sub-frame (a quarter of the pixels)
        bool full() const { return resolution >= 1.0 && stepScale <= 1.0 && !subFrame; }
    };

    InteractiveQuality() = default;
    explicit InteractiveQuality(Options options) : options_(options) {}

    /// The level for the next frame: reduced while `moving`, full when still.
    Level next(bool moving) const;
    /// Feedback: the frame drawn at `used` took `ms`.
    void frameDone(const Level& used, double ms);
    const Options& options() const { return options_; }
    void setOptions(const Options& options) { options_ = options; }
    /// Milliseconds per unit of work (a full-resolution, unit-step frame), as last measured.
    double fullFrameMs() const { return fullFrameMs_; }

private:
    Options options_;
    double fullFrameMs_ = 0.0;  // 0: not measured yet
};

}  // namespace hvx::core
