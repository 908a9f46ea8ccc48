#pragma once
#include <memory>
#include <string>

namespace hvx::render {

/// A headless OpenGL 4.5 core-profile context through EGL, with no X server: Mesa's
/// surfaceless platform (llvmpipe in CI), or an EGL device (NVIDIA on a bare GPU machine).
/// Functions are resolved by libepoxy. The context is current on the constructing thread.
///
/// Threading: use only on the thread that created it.
class EglOffscreenContext {
public:
    struct Info {
        int major = 0, minor = 0;
        std::string vendor, renderer, version;
    };
    /// Creates the context and makes it current; throws core::Error when no GL 4.5 is found.
    explicit EglOffscreenContext(bool debug = false);
    ~EglOffscreenContext();
    EglOffscreenContext(const EglOffscreenContext&) = delete;
    EglOffscreenContext& operator=(const EglOffscreenContext&) = delete;
    /// Makes the context current on the calling thread.
    void makeCurrent();
    /// Leaves no context current on the calling thread (before another API, such as GLX, takes it).
    void release();
    Info info() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace hvx::render
