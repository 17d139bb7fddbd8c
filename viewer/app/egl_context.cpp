// viewer/app/egl_context.cpp: see egl_context.h.
#include "viewer/app/egl_context.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <cstring>
#include <vector>

namespace mimetic::viewer {
namespace {

bool HasExtension(const char* list, const char* name) {
  if (!list) return false;
  const size_t n = std::strlen(name);
  for (const char* p = list; (p = std::strstr(p, name)) != nullptr; p += n)
    if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
  return false;
}

std::string ErrorName(EGLint e) {
  switch (e) {
    case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS: return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
    case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
    case EGL_BAD_SURFACE: return "EGL_BAD_SURFACE";
    default: return "EGL error " + std::to_string(e);
  }
}

struct Candidate {
  EGLDisplay display;
  std::string name;
};

// The displays worth trying, best first: each GPU device, Mesa's surfaceless platform, the
// default display (which needs a display server on most drivers).
std::vector<Candidate> Candidates() {
  std::vector<Candidate> out;
  const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);  // null without EXT_client_extensions
  auto get_platform_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
      eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (get_platform_display && HasExtension(client, "EGL_EXT_platform_device") &&
      HasExtension(client, "EGL_EXT_device_enumeration")) {
    auto query_devices =
        reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
    EGLDeviceEXT devices[16];
    EGLint n = 0;
    if (query_devices && query_devices(16, devices, &n)) {
      for (EGLint i = 0; i < n; ++i) {
        EGLDisplay d = get_platform_display(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr);
        if (d != EGL_NO_DISPLAY)
          out.push_back({d, "device " + std::to_string(i) + " (EGL_EXT_platform_device)"});
      }
    }
  }
  if (get_platform_display && HasExtension(client, "EGL_MESA_platform_surfaceless")) {
    EGLDisplay d = get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (d != EGL_NO_DISPLAY) out.push_back({d, "surfaceless (EGL_MESA_platform_surfaceless)"});
  }
  EGLDisplay d = eglGetDisplay(EGL_DEFAULT_DISPLAY);
  if (d != EGL_NO_DISPLAY) out.push_back({d, "the default display"});
  return out;
}

}  // namespace

bool EglContext::Create(std::string* error) {
  Destroy();
  std::string tried;
  for (const Candidate& c : Candidates()) {
    EGLDisplay d = c.display;
    EGLint major = 0, minor = 0;
    auto fail = [&](const std::string& what) {
      tried += "\n  " + c.name + ": " + what + " (" + ErrorName(eglGetError()) + ")";
    };
    if (!eglInitialize(d, &major, &minor)) {
      fail("eglInitialize failed");
      continue;
    }
    if (!eglBindAPI(EGL_OPENGL_API)) {
      fail("no desktop OpenGL");
      eglTerminate(d);
      continue;
    }
    const EGLint config_attribs[] = {EGL_SURFACE_TYPE,    EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE,
                                     EGL_OPENGL_BIT,      EGL_RED_SIZE,    8,
                                     EGL_GREEN_SIZE,      8,               EGL_BLUE_SIZE,
                                     8,                   EGL_DEPTH_SIZE,  24,
                                     EGL_NONE};
    EGLConfig config = nullptr;
    EGLint n = 0;
    if (!eglChooseConfig(d, config_attribs, &config, 1, &n) || n < 1) {
      fail("no OpenGL config with a pbuffer");
      eglTerminate(d);
      continue;
    }
    const EGLint context_attribs[] = {EGL_CONTEXT_MAJOR_VERSION,
                                      3,
                                      EGL_CONTEXT_MINOR_VERSION,
                                      3,
                                      EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                      EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                      EGL_NONE};
    EGLContext ctx = eglCreateContext(d, config, EGL_NO_CONTEXT, context_attribs);
    if (ctx == EGL_NO_CONTEXT) {
      fail("no OpenGL 3.3 core context");
      eglTerminate(d);
      continue;
    }
    const EGLint pbuffer_attribs[] = {EGL_WIDTH, 16, EGL_HEIGHT, 16, EGL_NONE};
    EGLSurface surface = eglCreatePbufferSurface(d, config, pbuffer_attribs);
    if (!eglMakeCurrent(d, surface, surface, ctx)) {
      fail("eglMakeCurrent failed");
      if (surface != EGL_NO_SURFACE) eglDestroySurface(d, surface);
      eglDestroyContext(d, ctx);
      eglTerminate(d);
      continue;
    }
    display_ = d;
    context_ = ctx;
    surface_ = surface;
    description_ = c.name + ", EGL " + std::to_string(major) + "." + std::to_string(minor);
    return true;
  }
  *error = "cannot make an OpenGL 3.3 core context through EGL" +
           (tried.empty() ? std::string(": no EGL display at all (is libEGL's driver installed?)")
                          : ":" + tried);
  return false;
}

void EglContext::Destroy() {
  if (!display_) return;
  eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  if (surface_ != EGL_NO_SURFACE) eglDestroySurface(display_, surface_);
  eglDestroyContext(display_, context_);
  eglTerminate(display_);
  display_ = context_ = surface_ = nullptr;
  description_.clear();
}

}  // namespace mimetic::viewer
