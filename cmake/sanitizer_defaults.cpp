// The sanitizer runtimes' options for every program of a GEOBRUSH_SANITIZE build (see
// GeoBrushSanitize.cmake): the runtimes call these hooks at start-up.

#include <dlfcn.h>

#define GEOBRUSH_SANITIZER_HOOK extern "C" __attribute__((visibility("default"), used))

GEOBRUSH_SANITIZER_HOOK const char* __asan_default_options() {
  return "detect_leaks=1:check_initialization_order=1:strict_init_order=1:"
         "detect_stack_use_after_return=0:abort_on_error=0";
}

GEOBRUSH_SANITIZER_HOOK const char* __ubsan_default_options() {
  return "print_stacktrace=1:halt_on_error=1";
}

// Leaks that belong to libraries, not to GeoBrush: each allocates once per process and keeps it
// to the end on purpose (caches, singletons, JIT code), so LeakSanitizer sees them unreleased at
// exit. A leak in GeoBrush's own code is never suppressed.
GEOBRUSH_SANITIZER_HOOK const char* __lsan_default_suppressions() {
  return
      // Qt's global statics: the plugin and codec registries, the font database, D-Bus, ICU.
      "leak:libQt6Core.so\n"
      "leak:libQt6Gui.so\n"
      "leak:libQt6Widgets.so\n"
      "leak:libQt6DBus.so\n"
      "leak:libQt6XcbQpa.so\n"
      "leak:libicuuc.so\n"
      "leak:libdbus-1.so\n"
      "leak:libfontconfig.so\n"
      "leak:libglib-2.0.so\n"
      "leak:libxcb.so\n"
      // Mesa's lavapipe and the LLVM it compiles shaders with, behind the Vulkan loader.
      "leak:libvulkan_lvp.so\n"
      "leak:libLLVM-15.so\n"
      "leak:libvulkan.so\n";
}

// The Vulkan loader unloads its driver in vkDestroyInstance, before the leak check at exit. What
// lavapipe keeps for the whole process (128 bytes from vkCreateInstance, measured with Mesa 22.3)
// is then referenced from unmapped globals, reported as leaked from "<unknown module>", and no
// suppression can name it. Opening the driver once more with RTLD_NODELETE keeps it mapped (about
// 40 ms at start-up); loaders from 1.3.259 have VK_LOADER_DISABLE_DYNAMIC_LIBRARY_UNLOADING for
// this, Debian 12's is 1.3.239. Nothing happens where lavapipe is not installed.
__attribute__((constructor)) static void keepVulkanDriverMapped() {
  dlopen("libvulkan_lvp.so", RTLD_LAZY | RTLD_NODELETE);
}
