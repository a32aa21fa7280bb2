#include "run_record_stream.hpp"

#include <cstdint>
#include <cstring>
#include <stdexcept>

namespace mh::cli {
namespace {

// Messages: a tag ('D' description, 'F' final description, 'R' row), the
// payload's length (uint64), the payload. Numbers in native byte order: the
// stream never leaves the machine.
template <class T>
void put(std::string& out, const T& v) {
  out.append(reinterpret_cast<const char*>(&v), sizeof(T));
}
void put_string(std::string& out, const std::string& s) {
  put(out, static_cast<uint64_t>(s.size()));
  out += s;
}
void put_strings(std::string& out, const std::vector<std::string>& v) {
  put(out, static_cast<uint64_t>(v.size()));
  for (const auto& s : v) put_string(out, s);
}

void append_message(std::string& out, char tag, const std::string& payload) {
  out += tag;
  put(out, static_cast<uint64_t>(payload.size()));
  out += payload;
}

// Reads a payload; throws std::out_of_range past its end.
struct Reader {
  const char* p;
  const char* end;
  template <class T>
  T get() {
    if (static_cast<size_t>(end - p) < sizeof(T)) throw std::out_of_range("cut");
    T v;
    std::memcpy(&v, p, sizeof(T));
    p += sizeof(T);
    return v;
  }
  std::string get_string() {
    const auto n = get<uint64_t>();
    if (static_cast<uint64_t>(end - p) < n) throw std::out_of_range("cut");
    std::string s(p, n);
    p += n;
    return s;
  }
  std::vector<std::string> get_strings() {
    const auto n = get<uint64_t>();
    std::vector<std::string> v;
    for (uint64_t i = 0; i < n; ++i) v.push_back(get_string());
    return v;
  }
};

void read_description(Reader& in, RunRecord& rec) {
  rec.label = in.get_string();
  rec.formulation = in.get_string();
  rec.integrator = in.get_string();
  rec.failed = in.get<uint8_t>() != 0;
  rec.failure = in.get_string();
  const bool has_time = in.get<uint8_t>() != 0;
  const auto time = in.get<double>();
  rec.failure_time = has_time ? std::optional<double>(time) : std::nullopt;
  rec.dt = in.get<double>();
  rec.t_end = in.get<double>();
  rec.names = in.get_strings();
  rec.units = in.get_strings();
  const auto n = in.get<uint64_t>();
  rec.info.clear();
  for (uint64_t i = 0; i < n; ++i) {
    VariableInfo v;
    v.name = in.get_string();
    v.qualified = in.get_string();
    v.unit = in.get_string();
    v.kind = in.get<uint32_t>();
    v.role = in.get_string();
    v.range_min = in.get<double>();
    v.range_max = in.get<double>();
    rec.info.push_back(v);
  }
  rec.num_coordinates = in.get<int32_t>();
  rec.num_states = in.get<int32_t>();
  rec.csv_path = in.get_string();
  rec.stopped_by = in.get<int32_t>();
  ExplicitStability& s = rec.stability;
  s.checks = in.get<int32_t>();
  s.unstable = in.get<uint8_t>() != 0;
  s.t = in.get<double>();
  s.step = static_cast<long>(in.get<int64_t>());
  s.h = in.get<double>();
  s.amplification = in.get<double>();
  const auto re = in.get<double>();
  s.eigenvalue = {re, in.get<double>()};
  s.stable_dt = in.get<double>();
  s.cpu_seconds = in.get<double>();
  s.skipped = in.get<int32_t>();
  rec.dissipators = in.get_strings();
  rec.dissipated.clear();
  for (size_t i = 0; i < rec.dissipators.size(); ++i) rec.dissipated.push_back(in.get<double>());
  rec.dissipation_parts = in.get_strings();
  rec.parts_dissipated.clear();
  for (size_t i = 0; i < rec.dissipation_parts.size(); ++i)
    rec.parts_dissipated.push_back(in.get<double>());
  if (rec.columns.size() != rec.names.size()) rec.columns.assign(rec.names.size(), {});
}

}  // namespace

void append_record_description(std::string& out, const RunRecord& rec, bool final) {
  std::string p;
  put_string(p, rec.label);
  put_string(p, rec.formulation);
  put_string(p, rec.integrator);
  put(p, static_cast<uint8_t>(rec.failed));
  put_string(p, rec.failure);
  put(p, static_cast<uint8_t>(rec.failure_time.has_value()));
  put(p, rec.failure_time.value_or(0.0));
  put(p, rec.dt);
  put(p, rec.t_end);
  put_strings(p, rec.names);
  put_strings(p, rec.units);
  put(p, static_cast<uint64_t>(rec.info.size()));
  for (const auto& v : rec.info) {
    put_string(p, v.name);
    put_string(p, v.qualified);
    put_string(p, v.unit);
    put(p, v.kind);
    put_string(p, v.role);
    put(p, v.range_min);
    put(p, v.range_max);
  }
  put(p, static_cast<int32_t>(rec.num_coordinates));
  put(p, static_cast<int32_t>(rec.num_states));
  put_string(p, rec.csv_path);
  put(p, static_cast<int32_t>(rec.stopped_by));
  const ExplicitStability& s = rec.stability;
  put(p, static_cast<int32_t>(s.checks));
  put(p, static_cast<uint8_t>(s.unstable));
  put(p, s.t);
  put(p, static_cast<int64_t>(s.step));
  put(p, s.h);
  put(p, s.amplification);
  put(p, s.eigenvalue.real());
  put(p, s.eigenvalue.imag());
  put(p, s.stable_dt);
  put(p, s.cpu_seconds);
  put(p, static_cast<int32_t>(s.skipped));
  put_strings(p, rec.dissipators);
  for (size_t i = 0; i < rec.dissipators.size(); ++i) put(p, rec.dissipated.at(i));
  put_strings(p, rec.dissipation_parts);
  for (size_t i = 0; i < rec.dissipation_parts.size(); ++i) put(p, rec.parts_dissipated.at(i));
  append_message(out, final ? 'F' : 'D', p);
}

void append_record_row(std::string& out, const RunRecord& rec, size_t row) {
  std::string p;
  for (const auto& column : rec.columns) put(p, column[row]);
  append_message(out, 'R', p);
}

DecodedRecord decode_record_stream(const std::string& bytes) {
  DecodedRecord d;
  Reader in{bytes.data(), bytes.data() + bytes.size()};
  try {
    while (in.p != in.end) {
      const char tag = in.get<char>();
      const auto n = in.get<uint64_t>();
      if (static_cast<uint64_t>(in.end - in.p) < n) break;  // cut by a crash
      Reader payload{in.p, in.p + n};
      in.p += n;
      if (tag == 'R') {
        if (n != d.record.columns.size() * sizeof(double)) break;
        for (auto& column : d.record.columns) column.push_back(payload.get<double>());
      } else if (tag == 'D' || tag == 'F') {
        read_description(payload, d.record);
        d.complete = tag == 'F';
      } else {
        break;
      }
    }
  } catch (const std::out_of_range&) {  // a cut message: keep what came before
  }
  return d;
}

}  // namespace mh::cli
