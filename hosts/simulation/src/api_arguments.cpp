#include "api_arguments.hpp"

#include <charconv>

namespace mh::embed {

std::string read_settings(const mhs_setting* settings, size_t count, OpenRequest& request) {
  if (count > 0 && settings == nullptr)
    return "settings is NULL with a count of " + std::to_string(count);
  for (size_t i = 0; i < count; ++i) {
    if (settings[i].path == nullptr || settings[i].value == nullptr)
      return "setting " + std::to_string(i) + " has a NULL path or value";
    request.settings.emplace_back(settings[i].path, settings[i].value);
  }
  return "";
}

std::string describe(const char* call, const std::vector<Variable>& table, uint32_t index,
                     mhs_variable_info* info) {
  const std::string name(call);
  if (info == nullptr) return name + ": info is NULL";
  if (info->struct_size < sizeof(mhs_variable_info))
    return name + ": info->struct_size is " + std::to_string(info->struct_size) + ", at least " +
           std::to_string(sizeof(mhs_variable_info)) + " expected";
  if (index >= table.size())
    return name + ": index " + std::to_string(index) + " is not below " +
           std::to_string(table.size());
  const Variable& v = table[index];
  info->kind = v.kind;
  info->name = v.name.c_str();
  info->qualified = v.qualified.c_str();
  info->unit = v.unit.c_str();
  info->min = v.min;
  info->max = v.max;
  return "";
}

std::string exact_text(double value) {
  char text[32];
  const auto written = std::to_chars(text, text + sizeof text, value);
  return std::string(text, written.ptr);
}

}  // namespace mh::embed
