#include "render/EglOffscreenContext.h"

#include <epoxy/egl.h>
#include <epoxy/gl.h>

#include <cstdio>
#include <string>
#include <vector>

#include "core/base/Error.h"

namespace hvx::render {

struct EglOffscreenContext::Impl {
    EGLDisplay display = EGL_NO_DISPLAY;
    EGLContext context = EGL_NO_CONTEXT;
};

namespace {
std::string hex(EGLint v) {
    char buf[16];
    std::snprintf(buf, sizeof buf, "%04X", unsigned(v));
    return buf;
}

EGLDisplay openDisplay() {
    const char* clientExt = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    const std::string ext = clientExt ? clientExt : "";
    if (ext.find("EGL_MESA_platform_surfaceless") != std::string::npos) {
        EGLDisplay d = eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
        if (d != EGL_NO_DISPLAY && eglInitialize(d, nullptr, nullptr)) return d;
    }
    if (ext.find("EGL_EXT_platform_device") != std::string::npos) {
        EGLint count = 0;
        eglQueryDevicesEXT(0, nullptr, &count);
        std::vector<EGLDeviceEXT> devices(std::size_t(count > 0 ? count : 0));
        if (count > 0 && eglQueryDevicesEXT(count, devices.data(), &count)) {
            for (EGLint i = 0; i < count; ++i) {
                EGLDisplay d = eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, devices[std::size_t(i)], nullptr);
                if (d != EGL_NO_DISPLAY && eglInitialize(d, nullptr, nullptr)) return d;
            }
        }
    }
    EGLDisplay d = eglGetDisplay(EGL_DEFAULT_DISPLAY);
    if (d != EGL_NO_DISPLAY && eglInitialize(d, nullptr, nullptr)) return d;
    throw core::Error("no headless EGL display (install Mesa's libegl-mesa0 and libgl1-mesa-dri)");
}
}  // namespace

EglOffscreenContext::EglOffscreenContext(bool debug) : impl_(std::make_unique<Impl>()) {
    impl_->display = openDisplay();
    if (!eglBindAPI(EGL_OPENGL_API)) throw core::Error("EGL: desktop OpenGL is not available");
    const EGLint configAttribs[] = {EGL_SURFACE_TYPE, 0, EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
    EGLConfig config = nullptr;
    EGLint n = 0;
    if (!eglChooseConfig(impl_->display, configAttribs, &config, 1, &n) || n < 1)
        throw core::Error("EGL: no OpenGL-capable configuration");
    const EGLint contextAttribs[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5,
                                     EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                     EGL_CONTEXT_OPENGL_DEBUG, debug ? EGL_TRUE : EGL_FALSE, EGL_NONE};
    impl_->context = eglCreateContext(impl_->display, config, EGL_NO_CONTEXT, contextAttribs);
    if (impl_->context == EGL_NO_CONTEXT) {
        eglTerminate(impl_->display);
        throw core::Error("EGL: the driver cannot create an OpenGL 4.5 core context");
    }
    makeCurrent();
}

EglOffscreenContext::~EglOffscreenContext() {
    release();
    eglDestroyContext(impl_->display, impl_->context);
    eglTerminate(impl_->display);
}

void EglOffscreenContext::makeCurrent() {
    if (!eglMakeCurrent(impl_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, impl_->context))
        throw core::Error("EGL: cannot make the surfaceless context current (error 0x" + hex(eglGetError()) + ")");
}

void EglOffscreenContext::release() {
    eglMakeCurrent(impl_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
}

EglOffscreenContext::Info EglOffscreenContext::info() const {
    Info i;
    glGetIntegerv(GL_MAJOR_VERSION, &i.major);
    glGetIntegerv(GL_MINOR_VERSION, &i.minor);
    auto str = [](GLenum e) {
        const auto* s = reinterpret_cast<const char*>(glGetString(e));
        return std::string(s ? s : "");
    };
    i.vendor = str(GL_VENDOR);
    i.renderer = str(GL_RENDERER);
    i.version = str(GL_VERSION);
    return i;
}

}  // namespace hvx::render
