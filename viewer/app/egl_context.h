// viewer/app/egl_context.h: an OpenGL 3.3 core context without a window or an X display, for
// the viewer's headless runs (--egl; docs/viewer.md "Headless"). GPU servers and containers
// have a driver but no display: EGL reaches the driver directly, through a GPU device
// (EGL_EXT_platform_device, how NVIDIA's driver offers it) or Mesa's surfaceless platform.
// The headless path draws into its own framebuffer object, so the context needs no surface
// beyond a small pbuffer to be made current on.
#pragma once

#include <string>

namespace mimetic::viewer {

class EglContext {
 public:
  EglContext() = default;
  ~EglContext() { Destroy(); }
  EglContext(const EglContext&) = delete;
  EglContext& operator=(const EglContext&) = delete;

  // Makes an OpenGL 3.3 core context current on the calling thread. False with `error` naming
  // what failed (no EGL display, no OpenGL config, the context refused) and what was tried.
  bool Create(std::string* error);
  void Destroy();
  // Which display was used: "device 0 (EGL_EXT_platform_device)", "surfaceless (Mesa)", ...
  const std::string& description() const { return description_; }

 private:
  void* display_ = nullptr;  // EGLDisplay
  void* context_ = nullptr;  // EGLContext
  void* surface_ = nullptr;  // EGLSurface (a 16 x 16 pbuffer, or none when surfaceless)
  std::string description_;
};

}  // namespace mimetic::viewer
