// RunState as bytes (run_state_bytes.hpp). Layout: a magic, the format
// version, this build's struct sizes and byte order, the payload's length,
// the payload (every field of RunState in declaration order, numbers in the
// machine's own representation), then FNV-1a 64 of everything before it.
#include "monohydra/core/run_state_bytes.hpp"

#include <complex>
#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>

namespace mh {

namespace {

constexpr char kMagic[8] = {'M', 'H', 'S', 'T', 'A', 'T', 'E', '\0'};
// 2: the model values (RunState::model_values); 3: the run's data
// (RunData) whole, then what RunState keeps beside it.
constexpr uint32_t kFormatVersion = 3;
constexpr uint32_t kByteOrder = 0x01020304u;
// TangentReuse keeps its members private and is copied as its bytes: the
// other build's layout must be this one's.
static_assert(std::is_trivially_copyable_v<TangentReuse>);
constexpr uint32_t kLayout = static_cast<uint32_t>(sizeof(TangentReuse)) << 16 |
                             static_cast<uint32_t>(sizeof(ExplicitStability));
constexpr size_t kHeader = sizeof kMagic + 3 * sizeof(uint32_t) + sizeof(uint64_t);

uint64_t fnv1a(const unsigned char* data, size_t size) {
  uint64_t h = 0xcbf29ce484222325ULL;
  for (size_t i = 0; i < size; ++i) {
    h ^= data[i];
    h *= 0x100000001b3ULL;
  }
  return h;
}

class Writer {
 public:
  explicit Writer(std::vector<unsigned char>& out) : out_(out) { out_.clear(); }
  void raw(const void* p, size_t n) {
    const auto* b = static_cast<const unsigned char*>(p);
    out_.insert(out_.end(), b, b + n);
  }
  template <class T>
  void put(T v) {
    static_assert(std::is_arithmetic_v<T>);
    raw(&v, sizeof v);
  }
  void flag(bool v) { put<uint8_t>(v ? 1 : 0); }
  void text(const std::string& s) {
    put<uint64_t>(s.size());
    raw(s.data(), s.size());
  }
  void vec(const Eigen::VectorXd& v) {
    put<uint64_t>(static_cast<uint64_t>(v.size()));
    raw(v.data(), sizeof(double) * static_cast<size_t>(v.size()));
  }
  template <class T>
  void list(const std::vector<T>& v) {
    put<uint64_t>(v.size());
    raw(v.data(), sizeof(T) * v.size());
  }
  void mat(const Eigen::MatrixXd& m) {
    put<uint64_t>(static_cast<uint64_t>(m.rows()));
    put<uint64_t>(static_cast<uint64_t>(m.cols()));
    raw(m.data(), sizeof(double) * static_cast<size_t>(m.size()));
  }
  size_t size() const { return out_.size(); }
  unsigned char* at(size_t offset) { return out_.data() + offset; }

  // One field of the state, by its type (walk below): the reader's
  // overloads read back what these write.
  void field(double v) { put(v); }
  void field(long v) { put<int64_t>(v); }
  void field(int v) { put<int32_t>(v); }
  void field(size_t v) { put<uint64_t>(v); }
  void field(bool v) { flag(v); }
  void field(const std::complex<double>& v) {
    put(v.real());
    put(v.imag());
  }
  void field(const std::string& v) { text(v); }
  void field(const Eigen::VectorXd& v) { vec(v); }
  void field(const Eigen::MatrixXd& v) { mat(v); }
  template <class T>
  void field(const std::vector<T>& v) {
    list(v);
  }
  void field(const TangentReuse& v) { raw(&v, sizeof v); }

 private:
  std::vector<unsigned char>& out_;
};

class Reader {
 public:
  Reader(const unsigned char* data, size_t size) : p_(data), left_(size) {}
  void raw(void* into, size_t n) {
    need(n);
    if (n > 0) std::memcpy(into, p_, n);
    p_ += n;
    left_ -= n;
  }
  template <class T>
  T get() {
    T v{};
    raw(&v, sizeof v);
    return v;
  }
  bool flag() {
    const auto v = get<uint8_t>();
    if (v > 1)
      throw RunStateError("the state's bytes are damaged (a flag reads " + std::to_string(v) + ")");
    return v == 1;
  }
  // A count of elements of `each` bytes that the bytes left can hold.
  size_t count(size_t each) {
    const auto n = get<uint64_t>();
    if (n > left_ / each)
      throw RunStateError("the state's bytes are cut short (a length of " + std::to_string(n) +
                          " reads past their end)");
    return static_cast<size_t>(n);
  }
  void text(std::string& s) {
    s.resize(count(1));
    raw(s.data(), s.size());
  }
  void vec(Eigen::VectorXd& v) {
    v.resize(static_cast<Eigen::Index>(count(sizeof(double))));
    raw(v.data(), sizeof(double) * static_cast<size_t>(v.size()));
  }
  template <class T>
  void list(std::vector<T>& v) {
    v.resize(count(sizeof(T)));
    raw(v.data(), sizeof(T) * v.size());
  }
  void mat(Eigen::MatrixXd& m) {
    const size_t rows = count(sizeof(double));
    const size_t cols = get<uint64_t>();
    if (rows != 0 && cols > left_ / sizeof(double) / rows)
      throw RunStateError("the state's bytes are cut short (a matrix of " + std::to_string(rows) +
                          " x " + std::to_string(cols) + " reads past their end)");
    m.resize(static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(cols));
    raw(m.data(), sizeof(double) * static_cast<size_t>(m.size()));
  }
  size_t left() const { return left_; }

  void field(double& v) { v = get<double>(); }
  void field(long& v) { v = static_cast<long>(get<int64_t>()); }
  void field(int& v) { v = get<int32_t>(); }
  void field(size_t& v) { v = static_cast<size_t>(get<uint64_t>()); }
  void field(bool& v) { v = flag(); }
  void field(std::complex<double>& v) {
    const double re = get<double>();
    v = {re, get<double>()};
  }
  void field(std::string& v) { text(v); }
  void field(Eigen::VectorXd& v) { vec(v); }
  void field(Eigen::MatrixXd& v) { mat(v); }
  template <class T>
  void field(std::vector<T>& v) {
    list(v);
  }
  void field(TangentReuse& v) { raw(&v, sizeof v); }

 private:
  void need(size_t n) const {
    if (n > left_) throw RunStateError("the state's bytes are cut short");
  }
  const unsigned char* p_;
  size_t left_;
};

// Every field of a run's data, in the bytes' order, written once for both
// directions: `Data` is const RunData with a Writer, RunData with a Reader.
template <class Data, class Io>
void walk_data(Data& s, Io& io) {
  auto& a = s.accepted;
  io.field(a.t);
  io.field(a.step);
  io.field(a.attempt_t);
  io.field(a.attempt_step);
  io.field(a.z);
  io.field(a.zd);
  io.field(a.zdd);
  io.field(a.started);
  auto& e = s.energy;
  for (auto* v : {&e.ke0, &e.pe0, &e.ke, &e.pe, &e.work, &e.power_k, &e.stored0, &e.stored,
                  &e.dissipated, &e.dissipation_k, &e.phi_norm})
    io.field(*v);
  for (auto* v : {&s.x, &s.xd, &s.xdd, &s.y, &s.ydot, &s.outputs}) io.field(*v);
  io.field(s.next_event);
  io.field(s.stability_due);
  io.field(s.stability_next_step);
  io.field(s.stability_worst_excess);
  auto& st = s.stability;
  io.field(st.checks);
  io.field(st.unstable);
  io.field(st.t);
  io.field(st.step);
  io.field(st.h);
  io.field(st.amplification);
  io.field(st.eigenvalue);
  io.field(st.stable_dt);
  io.field(st.cpu_seconds);
  io.field(st.skipped);
  auto& c = s.counters;
  for (auto* v : {&c.kinematics_passes, &c.residual_evaluations, &c.derivative_passes,
                  &c.constraint_position_passes, &c.constraint_rate_passes})
    io.field(*v);
  auto& ls = s.last_step;
  for (auto* v : {&ls.iterations, &ls.retries, &ls.tangents, &ls.damped}) io.field(*v);
  io.field(ls.converged);
  io.field(ls.unconverged);
  io.field(ls.increment_norms);
  io.field(ls.residual_norms);
  io.field(s.constraint_z);
  io.field(s.constraint_zd);
  io.field(s.constraint_positions_valid);
  io.field(s.constraint_rates_valid);
  io.field(s.reuse);
  io.field(s.rates_jacobian_valid);
  io.field(s.rates_jacobian);
  io.field(s.input_values);
  io.field(s.input_follows_table);
  io.field(s.input_jump_pending);
}

// A run's state: its key, its data, then what a snapshot keeps beside them.
template <class State, class Io>
void walk(State& s, Io& io) {
  io.field(s.run_key);
  walk_data(s.data, io);
  io.field(s.kept_tangent);
  io.field(s.model_values);
  io.field(s.part_sizes);
  io.field(s.part_bytes);
}

}  // namespace

void write_run_state_bytes(const RunState& s, std::vector<unsigned char>& out) {
  Writer w(out);
  w.raw(kMagic, sizeof kMagic);
  w.put(kFormatVersion);
  w.put(kByteOrder);
  w.put(kLayout);
  w.put<uint64_t>(0);  // the payload's length, once known
  walk(s, w);
  const uint64_t payload = w.size() - kHeader;
  std::memcpy(w.at(kHeader - sizeof payload), &payload, sizeof payload);
  w.put(fnv1a(w.at(0), w.size()));
}

void read_run_state_bytes(const unsigned char* data, std::size_t size, RunState& s) {
  if (data == nullptr || size < kHeader + sizeof(uint64_t) ||
      std::memcmp(data, kMagic, sizeof kMagic) != 0)
    throw RunStateError("the bytes are not a monohydra run state (" + std::to_string(size) +
                        " bytes without its header)");
  Reader head(data + sizeof kMagic, kHeader - sizeof kMagic);
  const auto version = head.get<uint32_t>();
  const auto order = head.get<uint32_t>();
  const auto layout = head.get<uint32_t>();
  const auto payload = head.get<uint64_t>();
  if (version != kFormatVersion)
    throw RunStateError("the state's bytes are of format version " + std::to_string(version) +
                        ", this build reads version " + std::to_string(kFormatVersion));
  if (order != kByteOrder || layout != kLayout)
    throw RunStateError(
        "the state's bytes were written by another build of monohydra (another byte order or "
        "layout): restore them with the build that saved them");
  if (payload != size - kHeader - sizeof(uint64_t))
    throw RunStateError("the state's bytes are cut short or run on: " + std::to_string(size) +
                        " bytes where the header says " +
                        std::to_string(payload + kHeader + sizeof(uint64_t)));
  uint64_t sum = 0;
  std::memcpy(&sum, data + size - sizeof sum, sizeof sum);
  if (sum != fnv1a(data, size - sizeof sum))
    throw RunStateError("the state's bytes are damaged (their checksum does not match)");

  Reader r(data + kHeader, static_cast<size_t>(payload));
  walk(s, r);
  for (uint8_t f : s.data.input_follows_table)
    if (f > 1)
      throw RunStateError("the state's bytes are damaged (a flag reads " + std::to_string(f) + ")");
  if (r.left() != 0)
    throw RunStateError("the state's bytes run on: " + std::to_string(r.left()) +
                        " bytes after its last field");
}

}  // namespace mh
