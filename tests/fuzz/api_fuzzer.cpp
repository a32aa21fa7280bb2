// libFuzzer target for the embedding API (monohydra/simulation.h): each
// input is a sequence of calls on one open four-bar, restored to its start
// first: steps, advances to any time (NaN, infinite, past), inputs set to
// any double, values and rows read with any index and any buffer size,
// snapshots saved, restored, written to bytes, damaged and read back.
// Every call must return a status of the five with a message ("" after
// MHS_OK), and a restored snapshot must put the run back at its time.
// Anything else (a crash, a sanitizer report, a hang) is a bug; .ci/fuzz
// runs it with the plugins of build/ on MONOHYDRA_PLUGIN_PATH.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "monohydra/simulation.h"

namespace {

struct Reader {
  const std::uint8_t* p;
  std::size_t left;
  std::uint8_t byte() {
    if (left == 0) return 0;
    --left;
    return *p++;
  }
  double number() {
    std::uint64_t bits = 0;
    for (int i = 0; i < 8; ++i) bits = bits << 8 | byte();
    double v = 0.0;
    std::memcpy(&v, &bits, sizeof v);
    return v;
  }
};

void check(mhs_simulation* sim, mhs_status st) {
  if (st < MHS_OK || st > MHS_FATAL) __builtin_trap();
  const char* message = mhs_message(sim);
  if (message == nullptr) __builtin_trap();
  // A call that did not return MHS_OK says why; one that did keeps what the
  // last one that did not said (simulation.h, 1.5).
  if (st != MHS_OK && message[0] == '\0') __builtin_trap();
}

struct Fixture {
  mhs_simulation* sim = nullptr;
  mhs_snapshot* start = nullptr;
  mhs_snapshot* a = nullptr;
  mhs_snapshot* b = nullptr;
  uint32_t count = 0;
  Fixture() {
    const mhs_setting settings[] = {{"t_end", "3"}};
    const char* model = std::getenv("MH_FUZZ_MODEL");
    if (mhs_open_file(model != nullptr ? model : "models/fourbar.yaml", settings, 1, &sim) >
            MHS_WARNING ||
        mhs_start(sim) > MHS_WARNING || mhs_snapshot_new(sim, &start) != MHS_OK ||
        mhs_snapshot_new(sim, &a) != MHS_OK || mhs_snapshot_new(sim, &b) != MHS_OK ||
        mhs_save(sim, start) != MHS_OK || mhs_variable_count(sim, &count) != MHS_OK) {
      std::fprintf(stderr, "api_fuzzer: cannot open the model: %s\n", mhs_message(sim));
      std::abort();
    }
  }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static Fixture f;
  mhs_simulation* sim = f.sim;
  if (mhs_restore(sim, f.start) != MHS_OK) __builtin_trap();
  Reader in{data, size};
  bool saved = false;
  double saved_t = 0.0;
  int steps = 0;
  std::vector<char> text;
  std::vector<double> values;
  while (in.left > 0) {
    double t = 0.0, dt = 0.0;
    check(sim, mhs_time(sim, &t, nullptr, &dt, nullptr));
    switch (in.byte() % 13) {
      case 0:
        if (++steps <= 200) check(sim, mhs_step(sim));
        break;
      case 1: {
        const std::uint8_t k = in.byte();
        const double to = k < 240 ? t + k * dt / 4 : k == 240 ? NAN : k == 241 ? INFINITY : -1.0;
        if (k < 240) steps += k / 4 + 1;
        if (steps <= 200 || k >= 240) check(sim, mhs_advance(sim, to));
        break;
      }
      case 2: {
        const uint32_t index = f.count - 1 - in.byte() % 3;  // the input, or outputs before it
        const double v = in.byte() % 2 != 0 ? in.number() : (in.byte() - 128) / 10.0;
        check(sim, mhs_set(sim, &index, 1, &v));
        break;
      }
      case 3: {
        uint32_t indices[4];
        const std::size_t n = in.byte() % 5;
        for (std::size_t i = 0; i < n; ++i) indices[i] = in.byte() % (f.count + 2);
        double out[4];
        check(sim, mhs_get(sim, indices, n, out));
        break;
      }
      case 4: {
        const mhs_status st = mhs_save(sim, f.a);
        check(sim, st);
        if (st == MHS_OK) {
          saved = true;
          saved_t = t;
        }
        break;
      }
      case 5: {
        const mhs_status st = mhs_restore(sim, f.a);
        check(sim, st);
        double back = 0.0;
        check(sim, mhs_time(sim, &back, nullptr, nullptr, nullptr));
        if (saved && st != MHS_OK && st != MHS_WARNING) __builtin_trap();
        if (saved && back != saved_t) __builtin_trap();
        break;
      }
      case 6: {
        const void* bytes = nullptr;
        std::size_t n = 0;
        const mhs_status st = mhs_snapshot_bytes(sim, f.a, &bytes, &n);
        check(sim, st);
        if (st != MHS_OK) break;
        std::vector<std::uint8_t> copy(static_cast<const std::uint8_t*>(bytes),
                                       static_cast<const std::uint8_t*>(bytes) + n);
        const std::uint8_t how = in.byte();
        if (how % 3 == 1 && !copy.empty()) copy[(in.byte() * 131u + in.byte()) % copy.size()] ^= 1;
        if (how % 3 == 2) copy.resize(copy.size() / 2);
        const mhs_status read = mhs_snapshot_read(sim, f.b, copy.data(), copy.size());
        check(sim, read);
        if (how % 3 != 0 && read == MHS_OK) __builtin_trap();  // damage must be seen
        check(sim, mhs_restore(sim, f.b));
        break;
      }
      case 7: {
        text.resize(in.byte() * 8);
        std::size_t length = 0;
        check(sim, mhs_row_text(sim, in.byte() % 2, text.empty() ? nullptr : text.data(),
                                text.size(), &length));
        break;
      }
      case 8: {
        mhs_variable_info info{};
        info.struct_size = in.byte();
        check(sim, mhs_variable(sim, in.byte(), &info));
        break;
      }
      case 9: {
        std::string name;
        for (std::uint8_t n = in.byte() % 12; n > 0; --n) name += static_cast<char>(in.byte());
        uint32_t index = 0;
        check(sim, mhs_find(sim, name.c_str(), &index));
        break;
      }
      case 10: {
        values.resize(in.byte() % 40);
        check(sim, mhs_row(sim, values.empty() ? nullptr : values.data(), values.size()));
        break;
      }
      case 11: {
        std::vector<std::uint8_t> junk(in.byte());
        for (auto& b : junk) b = in.byte();
        check(sim, mhs_snapshot_read(sim, f.b, junk.data(), junk.size()));
        break;
      }
      default: {
        int32_t due = 0;
        check(sim, mhs_row_due(sim, &due));
        break;
      }
    }
  }
  return 0;
}
