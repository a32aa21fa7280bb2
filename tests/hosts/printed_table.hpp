// Reading back the comparison table `monohydra compare` prints: cells are
// separated by two or more spaces and never empty.
#pragma once

#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace mh::test {

struct PrintedTable {
  std::string title;
  std::vector<std::string> header;
  std::map<std::string, std::vector<std::string>> rows;  // label -> the cells after it
  std::vector<std::string> notes;
  bool found = false;
  // The cell of `label` in the column headed `column` (the first one so
  // headed, or the `nth` one); "" when absent.
  std::string cell(const std::string& label, const std::string& column, int nth = 0) const {
    const auto r = rows.find(label);
    if (r == rows.end()) return "";
    for (size_t i = 1; i < header.size(); ++i)
      if (header[i] == column && nth-- == 0)
        return i - 1 < r->second.size() ? r->second[i - 1] : "";
    return "";
  }
};

inline std::vector<std::string> split_cells(const std::string& line) {
  std::vector<std::string> cells;
  std::string cell;
  size_t spaces = 0;
  for (char ch : line) {
    if (ch == ' ') {
      ++spaces;
      continue;
    }
    if (spaces >= 2 && !cell.empty()) {
      cells.push_back(cell);
      cell.clear();
    } else if (spaces == 1 && !cell.empty()) {
      cell += ' ';
    }
    spaces = 0;
    cell += ch;
  }
  if (!cell.empty()) cells.push_back(cell);
  return cells;
}

// The table whose title line starts with `title_prefix` in `output`.
inline PrintedTable parse_printed_table(const std::string& output,
                                        const std::string& title_prefix) {
  PrintedTable t;
  std::stringstream ss(output);
  std::string line;
  while (std::getline(ss, line))
    if (line.rfind(title_prefix, 0) == 0) break;
  if (ss.eof() && line.rfind(title_prefix, 0) != 0) return t;
  t.title = line;
  if (!std::getline(ss, line)) return t;
  t.header = split_cells(line);
  std::getline(ss, line);  // the rule
  while (std::getline(ss, line)) {
    if (line.empty()) break;
    if (line.rfind("  ", 0) == 0) {
      t.notes.push_back(line.substr(2));
      continue;
    }
    if (!t.notes.empty()) break;
    auto cells = split_cells(line);
    if (cells.size() != t.header.size()) break;  // past the table
    const std::string label = cells.front();
    cells.erase(cells.begin());
    t.rows[label] = cells;
  }
  t.found = !t.header.empty();
  return t;
}

}  // namespace mh::test
