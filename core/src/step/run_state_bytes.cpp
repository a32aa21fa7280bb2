// RunState as bytes (run_state_bytes.hpp). Layout: a magic, the format
// version, this build's struct sizes and byte order, the payload's length,
// the payload (every field of RunState in declaration order, numbers in the
// machine's own representation), then FNV-1a 64 of everything before it.
#include "monohydra/core/run_state_bytes.hpp"

#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>

namespace mh {

namespace {

constexpr char kMagic[8] = {'M', 'H', 'S', 'T', 'A', 'T', 'E', '\0'};
constexpr uint32_t kFormatVersion = 2;  // 2: the model values (RunState::model_values)
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

 private:
  void need(size_t n) const {
    if (n > left_) throw RunStateError("the state's bytes are cut short");
  }
  const unsigned char* p_;
  size_t left_;
};

}  // namespace

void write_run_state_bytes(const RunState& s, std::vector<unsigned char>& out) {
  Writer w(out);
  w.raw(kMagic, sizeof kMagic);
  w.put(kFormatVersion);
  w.put(kByteOrder);
  w.put(kLayout);
  w.put<uint64_t>(0);  // the payload's length, once known
  w.text(s.run_key);
  const AcceptedPoint& a = s.accepted;
  w.put(a.t);
  w.put<int64_t>(a.step);
  w.put(a.attempt_t);
  w.put<int64_t>(a.attempt_step);
  w.vec(a.z);
  w.vec(a.zd);
  w.vec(a.zdd);
  w.flag(a.started);
  const EnergyBalance& e = s.energy;
  for (double v : {e.ke0, e.pe0, e.ke, e.pe, e.work, e.power_k, e.stored0, e.stored, e.dissipated,
                   e.dissipation_k, e.phi_norm})
    w.put(v);
  for (const Eigen::VectorXd* v : {&s.x, &s.xd, &s.xdd, &s.y, &s.ydot, &s.outputs}) w.vec(*v);
  w.put<uint64_t>(s.next_event);
  w.flag(s.stability_due);
  w.put<int64_t>(s.stability_next_step);
  w.put(s.stability_worst_excess);
  const ExplicitStability& st = s.stability;
  w.put<int32_t>(st.checks);
  w.flag(st.unstable);
  w.put(st.t);
  w.put<int64_t>(st.step);
  w.put(st.h);
  w.put(st.amplification);
  w.put(st.eigenvalue.real());
  w.put(st.eigenvalue.imag());
  w.put(st.stable_dt);
  w.put(st.cpu_seconds);
  w.put<int32_t>(st.skipped);
  const Simulation::WorkCounters& c = s.counters;
  for (long v : {c.kinematics_passes, c.residual_evaluations, c.derivative_passes,
                 c.constraint_position_passes, c.constraint_rate_passes})
    w.put<int64_t>(v);
  const StepStats& ls = s.last_step;
  for (int v : {ls.iterations, ls.retries, ls.tangents, ls.damped}) w.put<int32_t>(v);
  w.flag(ls.converged);
  w.put(ls.unconverged);
  w.list(ls.increment_norms);
  w.list(ls.residual_norms);
  w.vec(s.constraint_z);
  w.vec(s.constraint_zd);
  w.flag(s.constraint_positions_valid);
  w.flag(s.constraint_rates_valid);
  w.raw(&s.reuse, sizeof s.reuse);
  w.list(s.kept_tangent);
  w.flag(s.rates_jacobian_valid);
  w.mat(s.rates_jacobian);
  w.list(s.input_values);
  w.list(s.input_follows_table);
  w.flag(s.input_jump_pending);
  w.list(s.model_values);
  w.list(s.part_sizes);
  w.list(s.part_bytes);
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
  r.text(s.run_key);
  AcceptedPoint& a = s.accepted;
  a.t = r.get<double>();
  a.step = static_cast<long>(r.get<int64_t>());
  a.attempt_t = r.get<double>();
  a.attempt_step = static_cast<long>(r.get<int64_t>());
  r.vec(a.z);
  r.vec(a.zd);
  r.vec(a.zdd);
  a.started = r.flag();
  EnergyBalance& e = s.energy;
  for (double* v : {&e.ke0, &e.pe0, &e.ke, &e.pe, &e.work, &e.power_k, &e.stored0, &e.stored,
                    &e.dissipated, &e.dissipation_k, &e.phi_norm})
    *v = r.get<double>();
  for (Eigen::VectorXd* v : {&s.x, &s.xd, &s.xdd, &s.y, &s.ydot, &s.outputs}) r.vec(*v);
  s.next_event = static_cast<size_t>(r.get<uint64_t>());
  s.stability_due = r.flag();
  s.stability_next_step = static_cast<long>(r.get<int64_t>());
  s.stability_worst_excess = r.get<double>();
  ExplicitStability& st = s.stability;
  st.checks = r.get<int32_t>();
  st.unstable = r.flag();
  st.t = r.get<double>();
  st.step = static_cast<long>(r.get<int64_t>());
  st.h = r.get<double>();
  st.amplification = r.get<double>();
  const double re = r.get<double>();
  st.eigenvalue = {re, r.get<double>()};
  st.stable_dt = r.get<double>();
  st.cpu_seconds = r.get<double>();
  st.skipped = r.get<int32_t>();
  Simulation::WorkCounters& c = s.counters;
  for (long* v : {&c.kinematics_passes, &c.residual_evaluations, &c.derivative_passes,
                  &c.constraint_position_passes, &c.constraint_rate_passes})
    *v = static_cast<long>(r.get<int64_t>());
  StepStats& ls = s.last_step;
  for (int* v : {&ls.iterations, &ls.retries, &ls.tangents, &ls.damped}) *v = r.get<int32_t>();
  ls.converged = r.flag();
  ls.unconverged = r.get<double>();
  r.list(ls.increment_norms);
  r.list(ls.residual_norms);
  r.vec(s.constraint_z);
  r.vec(s.constraint_zd);
  s.constraint_positions_valid = r.flag();
  s.constraint_rates_valid = r.flag();
  r.raw(&s.reuse, sizeof s.reuse);
  r.list(s.kept_tangent);
  s.rates_jacobian_valid = r.flag();
  r.mat(s.rates_jacobian);
  r.list(s.input_values);
  r.list(s.input_follows_table);
  for (uint8_t f : s.input_follows_table)
    if (f > 1)
      throw RunStateError("the state's bytes are damaged (a flag reads " + std::to_string(f) + ")");
  s.input_jump_pending = r.flag();
  r.list(s.model_values);
  r.list(s.part_sizes);
  r.list(s.part_bytes);
  if (r.left() != 0)
    throw RunStateError("the state's bytes run on: " + std::to_string(r.left()) +
                        " bytes after its last field");
}

}  // namespace mh
