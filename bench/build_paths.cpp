// The source tree and the built plugins (declared in bench_support.hpp),
// compiled into this file alone, so that the benchmarks' own objects are the
// same in any clone (a compiler cache serves them to a clone in another folder).
namespace mh::bench::paths {

extern const char* const source_dir = MH_SOURCE_DIR;
extern const char* const plugin_dir = MH_PLUGIN_DIR;

}  // namespace mh::bench::paths
