// A minimal mh_host for integrator tests: log and the four option calls over
// std::maps; every other service is NULL (integrators must not need them).
#pragma once

#include <map>
#include <string>
#include <vector>

#include "monohydra/host.h"

namespace mh_test {

class FakeHost {
 public:
  FakeHost() {
    api_.struct_size = sizeof(mh_host);
    api_.abi_version = MH_ABI_VERSION_INIT;
    api_.host_data = this;
    api_.log = log;
    api_.get_service = get_service;
    options_ = {sizeof(mh_options_service), option_number, option_string, option_table,
                option_error};
  }
  FakeHost(const FakeHost&) = delete;
  FakeHost& operator=(const FakeHost&) = delete;

  const mh_host* api() const { return &api_; }

  std::map<std::string, double> numbers;
  std::map<std::string, std::string> strings;
  std::map<std::string, std::vector<double>> tables;  // rows after rows
  std::vector<std::string> logs;                      // "<level>: <message>"
  std::vector<std::string> option_errors;             // keys given to option_error
  std::vector<std::string> asked;                     // keys asked for, in order

 private:
  mh_host api_{};
  mh_options_service options_{};

  // An integrator's one service: its options.
  static const void* get_service(const mh_host* h, const char* id) {
    return id != nullptr && std::string(id) == MH_SERVICE_OPTIONS ? &self(h).options_ : nullptr;
  }

  static FakeHost& self(const mh_host* h) { return *static_cast<FakeHost*>(h->host_data); }

  static void log(const mh_host* h, mh_log_level level, const char* message) {
    self(h).logs.push_back(std::to_string(static_cast<int>(level)) + ": " + message);
  }
  static mh_status option_number(const mh_host* h, const char* key, int required, double fallback,
                                 double* out) {
    FakeHost& f = self(h);
    f.asked.emplace_back(key);
    const auto it = f.numbers.find(key);
    if (it == f.numbers.end()) {
      if (required != 0) return MH_ERROR;
      *out = fallback;
      return MH_OK;
    }
    *out = it->second;
    return MH_OK;
  }
  static mh_status option_string(const mh_host* h, const char* key, int required,
                                 const char* fallback, const char** out) {
    FakeHost& f = self(h);
    f.asked.emplace_back(key);
    const auto it = f.strings.find(key);
    if (it == f.strings.end()) {
      if (required != 0) return MH_ERROR;
      *out = fallback;
      return MH_OK;
    }
    *out = it->second.c_str();
    return MH_OK;
  }
  static mh_status option_table(const mh_host* h, const char* key, int required, uint32_t columns,
                                const double** data, uint32_t* rows) {
    FakeHost& f = self(h);
    f.asked.emplace_back(key);
    const auto it = f.tables.find(key);
    if (it == f.tables.end() || columns == 0 || it->second.size() % columns != 0) {
      *data = nullptr;
      *rows = 0;
      return required != 0 || it != f.tables.end() ? MH_ERROR : MH_OK;
    }
    *data = it->second.data();
    *rows = static_cast<uint32_t>(it->second.size() / columns);
    return MH_OK;
  }
  static mh_status option_error(const mh_host* h, const char* key, const char* expected) {
    FakeHost& f = self(h);
    f.option_errors.emplace_back(key);
    f.logs.push_back(std::string("option '") + key + "': expected " + expected);
    return MH_ERROR;
  }
};

}  // namespace mh_test
