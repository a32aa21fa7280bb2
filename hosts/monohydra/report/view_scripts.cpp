#include "view_scripts.hpp"

// Each file is assembled into the program's read-only data as it is
// (.incbin), so that no generated source of a megabyte passes through the
// compiler; CMake names the files (MH_*_JS) and makes this object depend on
// them.
#define MH_STRINGIFY2(x) #x
#define MH_STRINGIFY(x) MH_STRINGIFY2(x)
#define MH_EMBED(name, path)                                                      \
  __asm__(".section .rodata\n.balign 16\n.hidden " #name "_begin\n.hidden " #name \
          "_end\n.global " #name "_begin\n.global " #name "_end\n" #name          \
          "_begin:\n"                                                             \
          ".incbin \"" path "\"\n" #name "_end:\n.byte 0\n.previous\n");          \
  extern "C" const char name##_begin[];                                           \
  extern "C" const char name##_end[];

MH_EMBED(mh_machine_view_js, MH_STRINGIFY(MH_MACHINE_VIEW_JS))
#ifdef MH_THREE_JS
MH_EMBED(mh_three_js, MH_STRINGIFY(MH_THREE_JS))
MH_EMBED(mh_orbit_controls_js, MH_STRINGIFY(MH_ORBIT_CONTROLS_JS))
#endif

namespace mh::cli {

std::string_view machine_view_source() {
  return {mh_machine_view_js_begin,
          static_cast<size_t>(mh_machine_view_js_end - mh_machine_view_js_begin)};
}

#ifdef MH_THREE_JS
std::string_view three_js_source() {
  return {mh_three_js_begin, static_cast<size_t>(mh_three_js_end - mh_three_js_begin)};
}
std::string_view orbit_controls_source() {
  return {mh_orbit_controls_js_begin,
          static_cast<size_t>(mh_orbit_controls_js_end - mh_orbit_controls_js_begin)};
}
#else
std::string_view three_js_source() {
  return {};
}
std::string_view orbit_controls_source() {
  return {};
}
#endif

}  // namespace mh::cli
