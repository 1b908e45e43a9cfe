// EGL display and context, and the offscreen framebuffers; design in headless.h.
//
// Display choice, in order:
//   1. an EGL device that is not a software renderer (EGL_EXT_device_enumeration; a device whose
//      extension string lists EGL_MESA_device_software is llvmpipe/softpipe). This is how NVIDIA's
//      and Mesa's GPU drivers run without a window system, so a machine with a GPU uses it.
//   2. Mesa's surfaceless platform (EGL_MESA_platform_surfaceless): no window system and no device
//      needed; on a machine without a GPU this is llvmpipe.
//   3. any EGL device, then 4. eglGetDisplay(EGL_DEFAULT_DISPLAY) (whatever the system offers).
// Nothing forces software rendering (no LIBGL_ALWAYS_SOFTWARE, no driver name).
//
// The display is never eglTerminate()d: EGL displays are per-process singletons per platform and
// native display, so terminating one would destroy every other context on it (tests create
// several HeadlessContexts in one process). The context itself is destroyed.
#include "render/headless.h"

#include <epoxy/egl.h>
#include <epoxy/gl.h>

#include <algorithm>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

namespace clothsim::render {
namespace {

bool has_extension(const char* list, std::string_view name) {
  if (list == nullptr) return false;
  std::string_view rest(list);
  while (!rest.empty()) {
    const std::size_t end = rest.find(' ');
    if (rest.substr(0, end) == name) return true;
    if (end == std::string_view::npos) break;
    rest.remove_prefix(end + 1);
  }
  return false;
}

std::string egl_error_name(EGLint error) {
  switch (error) {
    case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS: return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
    case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
    default: return "EGL error " + std::to_string(error);
  }
}

[[noreturn]] void fail(const std::string& what) {
  throw RenderError("headless rendering is unavailable: " + what +
                    " (rendering needs EGL with OpenGL 3.3 core, e.g. Mesa's libegl-mesa0 and libgl1-mesa-dri; "
                    "to run without images or video use --render none)");
}

struct Display {
  EGLDisplay display = EGL_NO_DISPLAY;
  std::string platform;
};

std::vector<EGLDeviceEXT> egl_devices(const char* client_extensions) {
  std::vector<EGLDeviceEXT> devices;
  if (!has_extension(client_extensions, "EGL_EXT_device_enumeration") &&
      !has_extension(client_extensions, "EGL_EXT_device_base")) {
    return devices;
  }
  EGLint count = 0;
  if (!eglQueryDevicesEXT(0, nullptr, &count) || count <= 0) return devices;
  devices.resize(static_cast<std::size_t>(count));
  if (!eglQueryDevicesEXT(count, devices.data(), &count)) return {};
  devices.resize(static_cast<std::size_t>(count));
  return devices;
}

bool initialise(EGLDisplay display) {
  if (display == EGL_NO_DISPLAY) return false;
  EGLint major = 0;
  EGLint minor = 0;
  return eglInitialize(display, &major, &minor) == EGL_TRUE;
}

Display open_display() {
  const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  const bool platform_base = has_extension(client, "EGL_EXT_platform_base");
  const std::vector<EGLDeviceEXT> devices = platform_base && has_extension(client, "EGL_EXT_platform_device")
                                                ? egl_devices(client)
                                                : std::vector<EGLDeviceEXT>{};
  auto is_software = [](EGLDeviceEXT device) {
    return has_extension(eglQueryDeviceStringEXT(device, EGL_EXTENSIONS), "EGL_MESA_device_software");
  };
  for (EGLDeviceEXT device : devices) {
    if (is_software(device)) continue;
    const EGLDisplay display = eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, device, nullptr);
    if (initialise(display)) return {display, "EGL device"};
  }
  if (platform_base && has_extension(client, "EGL_MESA_platform_surfaceless")) {
    const EGLDisplay display = eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (initialise(display)) return {display, "EGL surfaceless"};
  }
  for (EGLDeviceEXT device : devices) {
    const EGLDisplay display = eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, device, nullptr);
    if (initialise(display)) return {display, "EGL device"};
  }
  const EGLDisplay display = eglGetDisplay(EGL_DEFAULT_DISPLAY);
  if (initialise(display)) return {display, "EGL default display"};
  fail(client == nullptr ? "no EGL implementation found" : "no EGL display could be initialised");
}

}  // namespace

struct HeadlessContext::Impl {
  Display display;
  EGLContext context = EGL_NO_CONTEXT;
  int width = 0;
  int height = 0;
  int samples = 1;
  GLuint draw_framebuffer = 0;  // multisampled when samples > 1, else the same as resolve
  GLuint resolve_framebuffer = 0;
  GLuint renderbuffers[3] = {0, 0, 0};  // draw colour, draw depth, resolve colour

  void make_current() {
    if (eglGetCurrentContext() != context &&
        !eglMakeCurrent(display.display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {
      fail("eglMakeCurrent failed: " + egl_error_name(eglGetError()));
    }
  }

  void create_targets(int requested_samples) {
    GLint max_samples = 1;
    glGetIntegerv(GL_MAX_SAMPLES, &max_samples);
    samples = std::clamp(requested_samples, 1, std::max(1, static_cast<int>(max_samples)));
    glGenRenderbuffers(3, renderbuffers);
    glGenFramebuffers(1, &resolve_framebuffer);
    glBindRenderbuffer(GL_RENDERBUFFER, renderbuffers[2]);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
    glBindFramebuffer(GL_FRAMEBUFFER, resolve_framebuffer);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, renderbuffers[2]);
    if (samples > 1) {
      glGenFramebuffers(1, &draw_framebuffer);
      glBindRenderbuffer(GL_RENDERBUFFER, renderbuffers[0]);
      glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_RGBA8, width, height);
      glBindRenderbuffer(GL_RENDERBUFFER, renderbuffers[1]);
      glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_DEPTH_COMPONENT24, width, height);
      glBindFramebuffer(GL_FRAMEBUFFER, draw_framebuffer);
      glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, renderbuffers[0]);
    } else {
      draw_framebuffer = resolve_framebuffer;
      glBindRenderbuffer(GL_RENDERBUFFER, renderbuffers[1]);
      glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, width, height);
    }
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, renderbuffers[1]);
    for (const GLuint framebuffer : {draw_framebuffer, resolve_framebuffer}) {
      glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
      const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
      if (status != GL_FRAMEBUFFER_COMPLETE) {
        fail("the " + std::to_string(width) + "x" + std::to_string(height) +
             " offscreen framebuffer is incomplete (status 0x" +
             [status] {
               char hex[16];
               std::snprintf(hex, sizeof hex, "%x", status);
               return std::string(hex);
             }() +
             ")");
      }
    }
    glBindFramebuffer(GL_FRAMEBUFFER, draw_framebuffer);
  }
};

HeadlessContext::HeadlessContext(int width, int height, int samples) : impl_(std::make_unique<Impl>()) {
  Impl& impl = *impl_;
  if (width <= 0 || height <= 0)
    fail("image size " + std::to_string(width) + "x" + std::to_string(height) + " is not positive");
  impl.width = width;
  impl.height = height;
  impl.display = open_display();
  const EGLDisplay display = impl.display.display;
  if (!eglBindAPI(EGL_OPENGL_API)) fail("this EGL has no desktop OpenGL (eglBindAPI(EGL_OPENGL_API) failed)");

  // Any config that renders OpenGL: drawing goes to our own framebuffer objects, so the config's
  // colour and depth sizes do not matter. Without configs, EGL_KHR_no_config_context allows none.
  const EGLint config_attributes[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
  EGLConfig config = nullptr;
  EGLint config_count = 0;
  if (!eglChooseConfig(display, config_attributes, &config, 1, &config_count) || config_count < 1) {
    if (!has_extension(eglQueryString(display, EGL_EXTENSIONS), "EGL_KHR_no_config_context")) {
      fail("no EGL config renders OpenGL");
    }
    config = EGL_NO_CONFIG_KHR;
  }
  const EGLint context_attributes[] = {
      EGL_CONTEXT_MAJOR_VERSION,           3,       EGL_CONTEXT_MINOR_VERSION, 3, EGL_CONTEXT_OPENGL_PROFILE_MASK,
      EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
  impl.context = eglCreateContext(display, config, EGL_NO_CONTEXT, context_attributes);
  if (impl.context == EGL_NO_CONTEXT) {
    fail("no OpenGL 3.3 core context (" + egl_error_name(eglGetError()) + ") on " + impl.display.platform);
  }
  impl.make_current();
  if (epoxy_gl_version() < 33) fail("OpenGL " + std::to_string(epoxy_gl_version()) + " is below 3.3");
  impl.create_targets(samples);
  glViewport(0, 0, width, height);
}

HeadlessContext::~HeadlessContext() {
  Impl& impl = *impl_;
  if (impl.context == EGL_NO_CONTEXT) return;
  if (eglMakeCurrent(impl.display.display, EGL_NO_SURFACE, EGL_NO_SURFACE, impl.context)) {
    if (impl.draw_framebuffer != impl.resolve_framebuffer) glDeleteFramebuffers(1, &impl.draw_framebuffer);
    glDeleteFramebuffers(1, &impl.resolve_framebuffer);
    glDeleteRenderbuffers(3, impl.renderbuffers);
  }
  eglMakeCurrent(impl.display.display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  eglDestroyContext(impl.display.display, impl.context);
}

int HeadlessContext::width() const { return impl_->width; }
int HeadlessContext::height() const { return impl_->height; }
int HeadlessContext::samples() const { return impl_->samples; }

void HeadlessContext::bind() {
  impl_->make_current();
  glBindFramebuffer(GL_FRAMEBUFFER, impl_->draw_framebuffer);
  glViewport(0, 0, impl_->width, impl_->height);
}

void HeadlessContext::release() {
  if (eglGetCurrentContext() == impl_->context) {
    eglMakeCurrent(impl_->display.display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  }
}

void HeadlessContext::read(Image& image) {
  Impl& impl = *impl_;
  impl.make_current();
  if (impl.draw_framebuffer != impl.resolve_framebuffer) {
    glBindFramebuffer(GL_READ_FRAMEBUFFER, impl.draw_framebuffer);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, impl.resolve_framebuffer);
    glBlitFramebuffer(0, 0, impl.width, impl.height, 0, 0, impl.width, impl.height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
  }
  glBindFramebuffer(GL_READ_FRAMEBUFFER, impl.resolve_framebuffer);
  image.width = impl.width;
  image.height = impl.height;
  const std::size_t row = static_cast<std::size_t>(impl.width) * 3;
  image.rgb.resize(row * static_cast<std::size_t>(impl.height));
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, impl.width, impl.height, GL_RGB, GL_UNSIGNED_BYTE, image.rgb.data());
  // OpenGL's rows run bottom to top; images run top to bottom.
  std::vector<std::uint8_t> swap(row);
  for (int y = 0; y < impl.height / 2; ++y) {
    std::uint8_t* top = image.rgb.data() + static_cast<std::size_t>(y) * row;
    std::uint8_t* bottom = image.rgb.data() + static_cast<std::size_t>(impl.height - 1 - y) * row;
    std::memcpy(swap.data(), top, row);
    std::memcpy(top, bottom, row);
    std::memcpy(bottom, swap.data(), row);
  }
  glBindFramebuffer(GL_FRAMEBUFFER, impl.draw_framebuffer);
  const GLenum error = glGetError();
  if (error != GL_NO_ERROR)
    throw RenderError("reading the offscreen image failed: OpenGL error " + std::to_string(error));
}

std::string HeadlessContext::description() const {
  impl_->make_current();
  auto text = [](GLenum name) {
    const auto* value = reinterpret_cast<const char*>(glGetString(name));
    return std::string(value != nullptr ? value : "?");
  };
  return "OpenGL " + text(GL_VERSION) + ", " + text(GL_RENDERER) + ", " + impl_->display.platform + ", " +
         std::to_string(impl_->samples) + "x MSAA";
}

}  // namespace clothsim::render
