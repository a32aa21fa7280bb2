#include "case_expansion.hpp"

#include <algorithm>
#include <boost/random/lognormal_distribution.hpp>
#include <boost/random/mersenne_twister.hpp>
#include <boost/random/normal_distribution.hpp>
#include <boost/random/uniform_real_distribution.hpp>
#include <charconv>
#include <cmath>
#include <functional>

#include "monohydra/cpp/number_text.hpp"

namespace mh::cli::sweep {
namespace {

constexpr long kMaxValues = 1000000;

[[noreturn]] void fail(const ParameterSpec& p, const std::string& expectation) {
  throw InputError(p.mark, "parameters/" + p.path, expectation);
}

double number(const ParameterSpec& p, const YAML::Node& map, const char* key) {
  const YAML::Node n = map[key];
  if (!n) fail(p, std::string("expected ") + key + ": NUMBER");
  double v = 0.0;
  try {
    v = n.as<double>();
  } catch (const YAML::Exception&) {
    fail(p, std::string(key) + ": expected a finite number, got '" + n.Scalar() + "'");
  }
  if (!std::isfinite(v)) fail(p, std::string(key) + ": expected a finite number");
  return v;
}

long count(const ParameterSpec& p, const YAML::Node& map) {
  const double c = number(p, map, "count");
  if (c < 1 || c > kMaxValues || c != std::floor(c))
    fail(p, "count: expected a whole number from 1 to " + std::to_string(kMaxValues));
  return static_cast<long>(c);
}

YAML::Node scalar(double v) {
  return YAML::Node(number_text(v));
}

std::vector<YAML::Node> range(const ParameterSpec& p, const YAML::Node& map) {
  for (const auto& kv : map) {
    const std::string k = kv.first.Scalar();
    if (k != "from" && k != "to" && k != "count" && k != "step" && k != "scale")
      fail(p, "unknown key '" + k + "' in a range (from, to, count or step, scale)");
  }
  const double from = number(p, map, "from");
  const double to = number(p, map, "to");
  const std::string scale = map["scale"] ? map["scale"].Scalar() : "linear";
  if (scale != "linear" && scale != "log") fail(p, "scale: expected linear or log");
  std::vector<YAML::Node> out;
  if (map["step"]) {
    if (map["count"] || scale == "log")
      fail(p, "a range takes count (with scale) or step, not both");
    const double step = number(p, map, "step");
    if (step == 0.0 || (to - from) / step < 0.0)
      fail(p, "step: expected a non-zero step leading from 'from' towards 'to'");
    const double n = std::floor((to - from) / step * (1 + 1e-12) + 1e-9);
    if (n + 1 > kMaxValues) fail(p, "the range has more than 1000000 values");
    for (long i = 0; i <= static_cast<long>(n); ++i)
      out.push_back(scalar(from + static_cast<double>(i) * step));
    return out;
  }
  const long n = count(p, map);
  if (scale == "log" && (from <= 0.0 || to <= 0.0))
    fail(p, "a log range needs positive from and to");
  for (long i = 0; i < n; ++i) {
    const double f = n == 1 ? 0.0 : static_cast<double>(i) / static_cast<double>(n - 1);
    const double v = scale == "log" ? std::exp(std::log(from) + f * (std::log(to) - std::log(from)))
                                    : from + f * (to - from);
    out.push_back(scalar(i == n - 1 && n > 1 ? to : v));
  }
  return out;
}

std::vector<YAML::Node> draws(const ParameterSpec& p, const YAML::Node& map, std::uint64_t seed) {
  const std::string dist = map["distribution"].Scalar();
  const long n = count(p, map);
  std::vector<std::string> allowed = {"distribution", "count"};
  std::function<double(boost::random::mt19937_64&)> draw;
  if (dist == "uniform") {
    const double low = number(p, map, "low"), high = number(p, map, "high");
    if (!(low < high)) fail(p, "uniform: expected low < high");
    allowed.insert(allowed.end(), {"low", "high"});
    draw = [d = boost::random::uniform_real_distribution<double>(low, high)](
               boost::random::mt19937_64& g) mutable { return d(g); };
  } else if (dist == "normal") {
    const double mean = number(p, map, "mean"), sd = number(p, map, "std");
    if (!(sd > 0)) fail(p, "normal: expected std > 0");
    allowed.insert(allowed.end(), {"mean", "std"});
    draw = [d = boost::random::normal_distribution<double>(mean, sd)](
               boost::random::mt19937_64& g) mutable { return d(g); };
  } else if (dist == "lognormal") {
    // median and the standard deviation of the logarithm: a factor spread.
    const double median = number(p, map, "median"), sigma = number(p, map, "sigma");
    if (!(median > 0) || !(sigma > 0)) fail(p, "lognormal: expected median > 0 and sigma > 0");
    allowed.insert(allowed.end(), {"median", "sigma"});
    draw = [median, d = boost::random::normal_distribution<double>(0.0, sigma)](
               boost::random::mt19937_64& g) mutable { return median * std::exp(d(g)); };
  } else {
    fail(p,
         "distribution: expected uniform {low, high}, normal {mean, std} or lognormal "
         "{median, sigma}, got '" +
             dist + "'");
  }
  for (const auto& kv : map) {
    const std::string k = kv.first.Scalar();
    if (std::find(allowed.begin(), allowed.end(), k) == allowed.end())
      fail(p, "unknown key '" + k + "' for distribution " + dist);
  }
  boost::random::mt19937_64 generator(seed);
  std::vector<YAML::Node> out;
  for (long i = 0; i < n; ++i) out.push_back(scalar(draw(generator)));
  return out;
}

}  // namespace

std::string number_text(double value) {
  return monohydra::exact_number(value);
}

std::vector<YAML::Node> parameter_values(const Study& study, std::size_t parameter) {
  const ParameterSpec& p = study.parameters[parameter];
  const YAML::Node& v = p.values;
  if (v.IsScalar()) return {v};
  if (v.IsSequence()) {
    if (v.size() == 0) fail(p, "expected at least one value");
    std::vector<YAML::Node> out;
    for (std::size_t i = 0; i < v.size(); ++i) {
      if (!v[i].IsScalar()) fail(p, "expected a list of single values (numbers or names)");
      out.push_back(v[i]);
    }
    return out;
  }
  if (v.IsMap() && v["distribution"])
    // Each parameter its own stream: adding a parameter leaves the others' draws.
    return draws(p, v, study.seed * 1000003u + parameter);
  if (v.IsMap() && v["from"]) return range(p, v);
  fail(p,
       "expected a value, a list, a range {from, to, count|step} or a draw "
       "{distribution, count, ...}");
}

std::vector<std::string> varied_paths(const Study& study) {
  if (!study.listed.empty()) return study.listed_paths;
  std::vector<std::string> out;
  for (const auto& p : study.parameters) out.push_back(p.path);
  return out;
}

std::vector<Case> expand_cases(const Study& study) {
  std::vector<Overrides> combos;
  const auto paths = varied_paths(study);
  if (!study.listed.empty()) {
    for (const auto& listed : study.listed) {
      Overrides o;
      for (const auto& path : paths) {
        YAML::Node value;  // a path this combination leaves out: the model's own value
        for (const auto& [p, v] : listed)
          if (p == path) value = v;
        o.emplace_back(path, value);
      }
      combos.push_back(o);
    }
  } else {
    std::vector<std::vector<YAML::Node>> values;
    for (std::size_t i = 0; i < study.parameters.size(); ++i)
      values.push_back(parameter_values(study, i));
    if (study.combine == "zip") {
      for (std::size_t i = 1; i < values.size(); ++i)
        if (values[i].size() != values[0].size())
          throw InputError(study.parameters[i].mark, "parameters/" + study.parameters[i].path,
                           "combine: zip takes the i-th value of each parameter together: "
                           "expected " +
                               std::to_string(values[0].size()) + " values, got " +
                               std::to_string(values[i].size()));
      const std::size_t n = values.empty() ? 1 : values[0].size();
      for (std::size_t k = 0; k < n; ++k) {
        Overrides o;
        for (std::size_t i = 0; i < values.size(); ++i) o.emplace_back(paths[i], values[i][k]);
        combos.push_back(o);
      }
    } else {  // factorial: the last parameter varies fastest
      std::vector<std::size_t> at(values.size(), 0);
      double total = 1;
      for (const auto& v : values) total *= static_cast<double>(v.size());
      if (total > kMaxValues * 10.0)
        throw InputError(SourceMark{study.path, 0, 0}, "parameters",
                         "the full factorial has more than 10^7 cases");
      for (;;) {
        Overrides o;
        for (std::size_t i = 0; i < values.size(); ++i) o.emplace_back(paths[i], values[i][at[i]]);
        combos.push_back(o);
        std::size_t i = values.size();
        while (i > 0 && ++at[i - 1] == values[i - 1].size()) at[--i] = 0;
        if (i == 0) break;
      }
    }
  }
  std::vector<Case> cases;
  for (std::size_t m = 0; m < study.models.size(); ++m)
    for (const auto& o : combos) {
      Case c;
      c.index = static_cast<int>(cases.size());
      c.model = static_cast<int>(m);
      c.values = o;
      cases.push_back(c);
    }
  return cases;
}

}  // namespace mh::cli::sweep
