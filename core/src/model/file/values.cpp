// Reading one value of a model file: a string, a name, a bounded number, a
// 3-vector, an axis, an inertia matrix or a component option, each refused
// with the field and what was expected; plus the text helpers for messages.
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <charconv>
#include <climits>
#include <cmath>
#include <cstdio>
#include <string>

#include "monohydra/cpp/number_text.hpp"
#include "parser.hpp"

namespace mh::model_file_detail {

std::string join(const std::vector<std::string>& items) {
  std::string out;
  for (const auto& item : items) {
    if (!out.empty()) out += ", ";
    out += item;
  }
  return out;
}

std::string format_number(double value) {
  return monohydra::short_number(value);
}

std::string format_vector(const Eigen::Vector3d& v) {
  return "[" + format_number(v.x()) + ", " + format_number(v.y()) + ", " + format_number(v.z()) +
         "]";
}

std::string child_field(const std::string& base, const std::string& key) {
  return base.empty() ? key : base + "." + key;
}

std::string index_field(const std::string& base, std::size_t index) {
  return base + "[" + std::to_string(index) + "]";
}

// What a node is, for "got ..." in messages.
std::string describe(const YAML::Node& node) {
  switch (node.Type()) {
    case YAML::NodeType::Scalar:
      return "'" + node.Scalar() + "'";
    case YAML::NodeType::Sequence:
      return node.size() == 1 ? "a list of 1 item"
                              : "a list of " + std::to_string(node.size()) + " items";
    case YAML::NodeType::Map:
      return "a mapping";
    case YAML::NodeType::Null:
    case YAML::NodeType::Undefined:
    default:
      return "nothing";
  }
}

// A scalar written as a number: plain (not quoted) and fully parsed as a
// double. Accepts YAML's .inf/.nan spellings and "nan"/"inf" (to report them
// as non-finite rather than as non-numbers).
std::optional<double> scalar_number(const YAML::Node& node) {
  if (!node.IsScalar()) return std::nullopt;
  const std::string& tag = node.Tag();
  if (tag != "?" && tag != "tag:yaml.org,2002:float" && tag != "tag:yaml.org,2002:int") {
    return std::nullopt;  // quoted or explicitly tagged as something else: a string
  }
  std::string text = node.Scalar();
  if (text == ".inf" || text == ".Inf" || text == ".INF" || text == "+.inf" || text == "+.Inf" ||
      text == "+.INF") {
    return HUGE_VAL;
  }
  if (text == "-.inf" || text == "-.Inf" || text == "-.INF") return -HUGE_VAL;
  if (text == ".nan" || text == ".NaN" || text == ".NAN") return std::nan("");
  const char* begin = text.data();
  const char* end = text.data() + text.size();
  if (begin != end && *begin == '+') {
    ++begin;
    if (begin != end && *begin == '-') return std::nullopt;
  }
  if (begin == end) return std::nullopt;
  double value = 0.0;
  const auto result = std::from_chars(begin, end, value);
  if (result.ec != std::errc() || result.ptr != end) return std::nullopt;
  return value;
}

SourceMark Parser::mark(const YAML::Node& node) const {
  SourceMark m;
  m.file = file_;
  if (!node.IsDefined()) return m;
  YAML::Mark ym = node.Mark();
  if (node.IsNull()) {
    for (const auto& [value, key_mark] : null_value_marks_) {
      if (value.is(node)) ym = key_mark;
    }
  }
  if (!ym.is_null() && ym.line >= 0) {
    m.line = ym.line + 1;
    m.column = ym.column >= 0 ? ym.column + 1 : 0;
  }
  return m;
}

std::string Parser::string(const YAML::Node& node, const std::string& field) const {
  if (!node.IsScalar()) fail(node, field, "expected a string, got " + describe(node));
  return node.Scalar();
}

std::string Parser::name(const YAML::Node& node, const std::string& field) const {
  std::string text = string(node, field);
  if (text.empty()) fail(node, field, "expected a non-empty name");
  return text;
}

double Parser::checked_number(const YAML::Node& node, const std::string& field, const char* what,
                              const std::function<bool(double)>& ok) const {
  const std::optional<double> value = scalar_number(node);
  if (!value || !std::isfinite(*value) || !ok(*value)) {
    fail(node, field, std::string("expected ") + what + ", got " + describe(node));
  }
  return *value;
}

// A number whose magnitude is at most `limit` (unit in the message).
double Parser::bounded(double value, const YAML::Node& node, const std::string& field, double limit,
                       const char* unit) const {
  if (std::abs(value) > limit)
    fail(node, field,
         "expected a magnitude up to " + format_number(limit) + " " + unit + ", got " +
             describe(node));
  return value;
}
Eigen::Vector3d Parser::length3(const YAML::Node& node, const std::string& field) const {
  Eigen::Vector3d v = vector3(node, field);
  for (std::size_t i = 0; i < 3; ++i)
    bounded(v[static_cast<Eigen::Index>(i)], node[i], index_field(field, i), kMaxLength, "m");
  return v;
}

int Parser::integer_at_least(const YAML::Node& node, const std::string& field, int minimum) const {
  const std::string what = "an integer >= " + std::to_string(minimum);
  const double value = checked_number(node, field, what.c_str(), [minimum](double v) {
    return v == std::floor(v) && v >= minimum && v <= static_cast<double>(INT_MAX);
  });
  return static_cast<int>(value);
}

bool Parser::boolean(const YAML::Node& node, const std::string& field) const {
  if (node.IsScalar()) {
    const std::string& t = node.Scalar();
    if (t == "true") return true;
    if (t == "false") return false;
  }
  fail(node, field, "expected true or false, got " + describe(node));
}

Eigen::Vector3d Parser::vector3(const YAML::Node& node, const std::string& field) const {
  if (!node.IsSequence() || node.size() != 3) {
    fail(node, field, "expected a list of 3 numbers, got " + describe(node));
  }
  Eigen::Vector3d v;
  for (std::size_t i = 0; i < 3; ++i) {
    v[static_cast<Eigen::Index>(i)] = number(node[i], index_field(field, i));
  }
  return v;
}

// A direction: any non-zero vector, returned normalized.
Eigen::Vector3d Parser::axis(const YAML::Node& node, const std::string& field) const {
  const Eigen::Vector3d v = vector3(node, field);
  const double norm = v.norm();
  if (!(norm > 1e-12) || !std::isfinite(norm)) {
    fail(node, field, "expected a non-zero axis, got " + format_vector(v));
  }
  return v / norm;
}

// Diagonal [Ixx, Iyy, Izz] or a full 3x3 nested list; symmetric and
// positive semidefinite.
Eigen::Matrix3d Parser::inertia(const YAML::Node& node, const std::string& field) const {
  const std::string expected =
      "expected a list of 3 non-negative numbers (the diagonal) or a 3x3 nested list";
  if (!node.IsSequence() || node.size() != 3) {
    fail(node, field, expected + ", got " + describe(node));
  }
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
  if (!node[0].IsSequence()) {
    for (std::size_t i = 0; i < 3; ++i) {
      const auto k = static_cast<Eigen::Index>(i);
      inertia(k, k) = bounded(non_negative(node[i], index_field(field, i)), node[i],
                              index_field(field, i), kMaxMass, "kg m^2");
    }
    return inertia;
  }
  for (std::size_t i = 0; i < 3; ++i) {
    const YAML::Node row = node[i];
    const std::string row_field = index_field(field, i);
    if (!row.IsSequence() || row.size() != 3) {
      fail(row, row_field, "expected a row of 3 numbers, got " + describe(row));
    }
    for (std::size_t j = 0; j < 3; ++j) {
      inertia(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) =
          bounded(number(row[j], index_field(row_field, j)), row[j], index_field(row_field, j),
                  kMaxMass, "kg m^2");
    }
  }
  const double scale = std::max(1.0, inertia.cwiseAbs().maxCoeff());
  for (Eigen::Index i = 0; i < 3; ++i) {
    for (Eigen::Index j = i + 1; j < 3; ++j) {
      if (std::abs(inertia(i, j) - inertia(j, i)) > 1e-9 * scale) {
        fail(node, field,
             "expected a symmetric matrix, but [" + std::to_string(i) + "][" + std::to_string(j) +
                 "] = " + format_number(inertia(i, j)) + " differs from [" + std::to_string(j) +
                 "][" + std::to_string(i) + "] = " + format_number(inertia(j, i)));
      }
    }
  }
  inertia = 0.5 * (inertia + inertia.transpose()).eval();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(inertia, Eigen::EigenvaluesOnly);
  const Eigen::Vector3d& eigenvalues = solver.eigenvalues();
  if (eigenvalues.minCoeff() < -1e-10 * scale) {
    fail(node, field,
         "expected a positive semidefinite matrix, got eigenvalues " + format_vector(eigenvalues));
  }
  return inertia;
}

// A component option: number, string, a flat list of numbers (one row) or
// a list of equal-length lists of numbers (a table).
OptionValue Parser::option(const YAML::Node& node, const std::string& field) const {
  static const std::string expected =
      "expected a number, a string, a list of numbers or a list of equal-length lists of "
      "numbers";
  OptionValue value;
  value.mark = mark(node);
  if (node.IsScalar()) {
    value.text = node.Scalar();
    if (const auto number = scalar_number(node)) {
      if (!std::isfinite(*number)) {
        fail(node, field, "expected a finite number, got " + describe(node));
      }
      value.kind = OptionValue::Kind::number;
      value.number = *number;
    } else {
      value.kind = OptionValue::Kind::string;
    }
    return value;
  }
  if (!node.IsSequence() || node.size() == 0) {
    fail(node, field, expected + ", got " + describe(node));
  }
  value.kind = OptionValue::Kind::table;
  if (!node[0].IsSequence()) {
    value.rows = 1;
    value.columns = static_cast<int>(node.size());
    for (std::size_t i = 0; i < node.size(); ++i) {
      value.table.push_back(number(node[i], index_field(field, i)));
    }
    return value;
  }
  value.rows = static_cast<int>(node.size());
  value.columns = static_cast<int>(node[0].size());
  for (std::size_t i = 0; i < node.size(); ++i) {
    const YAML::Node row = node[i];
    const std::string row_field = index_field(field, i);
    if (!row.IsSequence() || row.size() == 0) {
      fail(row, row_field,
           "expected a non-empty list of numbers (a table row), got " + describe(row));
    }
    if (static_cast<int>(row.size()) != value.columns) {
      fail(row, row_field,
           "expected " + std::to_string(value.columns) +
               " numbers like the first row (all rows of a table have the same length), got " +
               describe(row));
    }
    for (std::size_t j = 0; j < row.size(); ++j) {
      value.table.push_back(number(row[j], index_field(row_field, j)));
    }
  }
  return value;
}

void Parser::check_unique(std::map<std::string, SourceMark>& seen, const std::string& value,
                          const YAML::Node& node, const std::string& field,
                          const char* what) const {
  const auto [it, inserted] = seen.emplace(value, mark(node));
  if (!inserted) {
    fail(node, field,
         std::string("duplicate ") + what + " name '" + value + "' (first defined at " +
             location(it->second) + ")");
  }
}

std::string Parser::location(const SourceMark& m) {
  return "line " + std::to_string(m.line) + ", column " + std::to_string(m.column);
}

}  // namespace mh::model_file_detail
