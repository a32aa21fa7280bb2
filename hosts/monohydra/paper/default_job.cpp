// The default job (`monohydra` with no arguments): the paper's comparison of
// the formulations models/paper-reference.yaml lists on its two case studies,
// the paper's numbers beside ours, a report for each.
#include <algorithm>
#include <filesystem>
#include <iostream>

#include "case_studies.hpp"
#include "commands.hpp"
#include "compare.hpp"
#include "monohydra/core/input_error.hpp"

namespace fs = std::filesystem;

namespace mh::cli {

int run_default() {
  const std::string path = case_studies_path();
  std::vector<CaseStudy> studies;
  try {
    studies = load_case_studies(path);
  } catch (const InputError& err) {
    std::cerr << "monohydra: " << err.what() << '\n';
    return 2;
  }
  // Every model must be there before anything runs.
  int missing = 0;
  std::error_code ec;
  for (const auto& s : studies) {
    if (fs::is_regular_file(s.model_path, ec)) continue;
    std::cerr << "monohydra: the default job compares the formulations on the paper's case "
                 "studies, but the model of the "
              << s.name << " is missing: " << s.model_path << " (listed in " << path << ")\n";
    ++missing;
  }
  if (missing > 0) return 2;

  std::cout << "monohydra: comparing the formulations on the paper's case studies (" << path
            << ")\n";
  int code = 0;
  std::vector<std::string> reports;
  for (const auto& s : studies) {
    std::cout << '\n';
    CompareJob job;
    job.model_path = s.model_path;
    job.formulations = s.formulations;
    job.report_dir = s.report_dir;
    job.study = &s;
    const int c = run_comparison(job, std::cout);
    if (c == 2) return 2;
    code = std::max(code, c);
    reports.push_back(
        fs::absolute(fs::path(s.report_dir) / "report.html").lexically_normal().string());
  }
  std::cout << "\nreports (open in a browser; each folder also holds the runs' CSVs):\n";
  for (const auto& r : reports) std::cout << "  " << r << '\n';
  return code;
}

}  // namespace mh::cli
