// A shared library without the GeoBrush entry points.
extern "C" __attribute__((visibility("default"))) int some_other_library_function() {
  return 7;
}
