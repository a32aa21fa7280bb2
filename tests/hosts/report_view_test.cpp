// The report's animated 3D view (report/machine_view.*) in a real browser:
// Debian's headless Chromium with software WebGL (SwiftShader) opens the
// four-bar's comparison report and the excavator's run report, and
//  - the canvas becomes ready within 8 s of virtual time, with no console
//    error, no uncaught exception and no load from the network;
//  - at t = 0 and at the end, the magenta marker on the screen lies within
//    5 px of where the body point it marks, computed here from the CSV's
//    coordinates with the core's kinematics, projects with the view's own
//    camera (the matrix the canvas publishes);
//  - the canvas is not blank (pixel variance), and the excavator's page is
//    at most 10 MB.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "monohydra/core/data.hpp"
#include "monohydra/core/kinematics.hpp"
#include "monohydra/core/model_file.hpp"

#ifdef MH_HAVE_LIBPNG
#include <png.h>
#endif

namespace mh::test {
namespace {

namespace fs = std::filesystem;

constexpr int kWindowWidth = 900;
constexpr int kWindowHeight = 1000;

// The value of attribute `name` of the canvas in a dumped DOM ("" if absent),
// with the entities Chromium writes undone.
std::string canvas_attribute(const std::string& dom, const std::string& name) {
  const size_t canvas = dom.find("<canvas id=\"mh-view-canvas\"");
  if (canvas == std::string::npos) return "";
  const size_t end = dom.find('>', canvas);
  const std::string tag = dom.substr(canvas, end - canvas);
  const std::string key = " " + name + "=\"";
  const size_t at = tag.find(key);
  if (at == std::string::npos) return "";
  const size_t begin = at + key.size();
  std::string value = tag.substr(begin, tag.find('"', begin) - begin);
  for (size_t q = value.find("&quot;"); q != std::string::npos; q = value.find("&quot;"))
    value.replace(q, 6, "\"");
  return value;
}

// The numbers of a JSON array or object text, in order.
std::vector<double> numbers_in(const std::string& text) {
  std::vector<double> out;
  const char* p = text.c_str();
  while (*p != '\0') {
    if ((*p >= '0' && *p <= '9') || *p == '-' || *p == '.') {
      char* end = nullptr;
      out.push_back(std::strtod(p, &end));
      p = end;
    } else {
      ++p;
    }
  }
  return out;
}

// A copy of the report whose first script records every console.error,
// uncaught error and rejected promise in an attribute of <html>: the test's
// own instrument, beside Chromium's log.
fs::path instrumented_copy(const fs::path& report) {
  std::string html = read_text(report);
  const std::string recorder =
      "<script>//<![CDATA[\n(function(){var e=[];function keep(m){e.push(String(m));"
      "document.documentElement.setAttribute('data-test-errors',JSON.stringify(e));}"
      "var ce=console.error;console.error=function(){keep(Array.prototype.join.call(arguments,"
      "' '));ce.apply(console,arguments);};window.addEventListener('error',function(ev){"
      "keep(ev.message);});window.addEventListener('unhandledrejection',function(ev){"
      "keep(ev.reason);});})();\n//]]></script>\n";
  const size_t head = html.find("<head>");
  html.insert(head + 6, recorder);
  const fs::path copy = report.parent_path() / "report-instrumented.html";
  std::ofstream(copy, std::ios::binary) << html;
  return copy;
}

// Chromium, headless, software WebGL, the network unreachable. One launch
// dumps the DOM and takes the screenshot of the same page after the same
// virtual time (a launch costs some 6 s here, most of it Chromium starting).
std::string chromium(const fs::path& page, const std::string& hash, const fs::path& png) {
  return "chromium --headless --no-sandbox --use-angle=swiftshader --enable-unsafe-swiftshader "
         "--hide-scrollbars --force-device-scale-factor=1 --window-size=" +
         std::to_string(kWindowWidth) + "," + std::to_string(kWindowHeight) +
         " --virtual-time-budget=8000 --host-resolver-rules='MAP * ~NOTFOUND' "
         "--proxy-server=127.0.0.1:9 --enable-logging=stderr --v=0 --dump-dom --screenshot='" +
         png.string() + "' 'file://" + page.string() + "#t=" + hash + "'";
}

struct Screen {
  unsigned width = 0, height = 0;
  std::vector<unsigned char> rgb;
};

#ifdef MH_HAVE_LIBPNG
bool read_png(const fs::path& path, Screen& out) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  if (png_image_begin_read_from_file(&image, path.string().c_str()) == 0) return false;
  image.format = PNG_FORMAT_RGB;
  out.rgb.resize(PNG_IMAGE_SIZE(image));
  if (png_image_finish_read(&image, nullptr, out.rgb.data(), 0, nullptr) == 0) return false;
  out.width = image.width;
  out.height = image.height;
  return true;
}
#endif

// What the view showed at one time, and where the marker should be.
struct Look {
  std::string state;  // data-monohydra-view
  std::string error;  // data-monohydra-error
  std::string recorded_errors;
  std::string log;  // Chromium's
  double t = NAN;
  std::vector<double> camera, rect, marker;
};

Look look_at(const fs::path& page, const std::string& hash, const fs::path& png) {
  Look look;
  fs::remove(png);
  const CliResult dom = run_shell(chromium(page, hash, png));
  look.log = dom.output;
  look.state = canvas_attribute(dom.output, "data-monohydra-view");
  look.error = canvas_attribute(dom.output, "data-monohydra-error");
  const size_t errors = dom.output.find("data-test-errors=\"");
  if (errors != std::string::npos) look.recorded_errors = dom.output.substr(errors, 200);
  const std::string time = canvas_attribute(dom.output, "data-monohydra-time");
  if (!time.empty()) look.t = std::stod(time);
  look.camera = numbers_in(canvas_attribute(dom.output, "data-monohydra-camera"));
  look.rect = numbers_in(canvas_attribute(dom.output, "data-monohydra-rect"));
  look.marker = numbers_in(canvas_attribute(dom.output, "data-monohydra-marker"));
  return look;
}

// The console lines of Chromium's log but the GPU's own performance notes.
std::vector<std::string> console_lines(const std::string& log) {
  std::vector<std::string> lines;
  std::istringstream in(log);
  for (std::string line; std::getline(in, line);)
    if (line.find(":CONSOLE") != std::string::npos &&
        line.find("GL Driver Message") == std::string::npos)
      lines.push_back(line);
  return lines;
}

// The model's body point the view marks, at the CSV's row `row`, projected
// with the view's camera to page pixels.
Eigen::Vector2d expected_pixel(const ModelFile& file, const Csv& csv, size_t row,
                               const Look& look) {
  const Model& m = file.model;
  Eigen::VectorXd z(static_cast<Eigen::Index>(m.bodies.size()));
  for (size_t j = 0; j < m.bodies.size(); ++j)
    z[static_cast<Eigen::Index>(j)] = csv["z" + std::to_string(j + 1)][row];
  Data data(m);
  forward_kinematics(m, data, z, Eigen::VectorXd::Zero(z.size()));
  const BodyPoint marked{static_cast<int>(look.marker[0]),
                         Eigen::Vector3d(look.marker[1], look.marker[2], look.marker[3])};
  const Eigen::Vector3d p = point_position(data, marked);
  const Eigen::Map<const Eigen::Matrix4d> M(look.camera.data());
  const Eigen::Vector4d clip = M * Eigen::Vector4d(p.x(), p.y(), p.z(), 1.0);
  const double x = clip.x() / clip.w(), y = clip.y() / clip.w();
  return {look.rect[0] + 0.5 * (x + 1.0) * look.rect[2],
          look.rect[1] + 0.5 * (1.0 - y) * look.rect[3]};
}

struct Case {
  const char* name;
  const char* command;  // the monohydra arguments before --report DIR
  const char* model;
  const char* csv;  // the solid run's CSV in DIR
};

void PrintTo(const Case& c, std::ostream* os) {
  *os << c.name;
}

class ReportView : public ::testing::TestWithParam<Case> {};

TEST_P(ReportView, ChromiumDrawsTheMarkedPointWhereTheCsvPutsIt) {
  if (!have_program("chromium")) GTEST_SKIP() << "chromium is not installed";
#ifndef MH_HAVE_LIBPNG
  GTEST_SKIP() << "built without libpng: cannot read the screenshot";
#else
  const Case& c = GetParam();
  const fs::path dir = scratch_dir(std::string("view-") + c.name);
  const CliResult made =
      run_cli(std::string(c.command) + " " + shipped_model(c.model) + " --report " + dir.string());
  ASSERT_EQ(made.code, 0) << made.output;
  const fs::path report = dir / "report.html";
  const std::string html = read_text(report);
  ASSERT_NE(html.find("id=\"mh-view-canvas\""), std::string::npos)
      << "no 3D view (built without libjs-three?)";
  EXPECT_LE(fs::file_size(report), 10u * 1000u * 1000u) << "the report is above 10 MB";
  const fs::path page = instrumented_copy(report);

  const ModelFile file = load_model_file(shipped_model(c.model));
  const Csv csv = read_csv(dir / c.csv);
  ASSERT_GT(csv["t"].size(), 1u);
  const size_t rows[] = {0, csv["t"].size() - 1};
  const char* hashes[] = {"0", "end"};
  for (int k = 0; k < 2; ++k) {
    SCOPED_TRACE(std::string("t=") + hashes[k]);
    const fs::path png = dir / (std::string("shot-") + hashes[k] + ".png");
    const Look look = look_at(page, hashes[k], png);
    // Ready within the 8 s of virtual time, with nothing said on the console.
    ASSERT_EQ(look.state, "ready") << look.error << "\n" << look.log;
    EXPECT_TRUE(look.recorded_errors.empty()) << look.recorded_errors;
    for (const auto& line : console_lines(look.log)) ADD_FAILURE() << "console: " << line;
    ASSERT_EQ(look.camera.size(), 16u);
    ASSERT_EQ(look.rect.size(), 4u);
    ASSERT_EQ(look.marker.size(), 4u);
    EXPECT_NEAR(look.t, csv["t"][rows[k]], 1e-9) << "the view shows another row";

    Screen screen;
    ASSERT_TRUE(read_png(png, screen)) << look.log;
    ASSERT_EQ(screen.width, static_cast<unsigned>(kWindowWidth));

    // The marker's pixels (magenta) inside the canvas, and their centre.
    const int x0 = static_cast<int>(look.rect[0]), y0 = static_cast<int>(look.rect[1]);
    const int x1 = std::min<int>(static_cast<int>(screen.width),
                                 static_cast<int>(look.rect[0] + look.rect[2]));
    const int y1 = std::min<int>(static_cast<int>(screen.height),
                                 static_cast<int>(look.rect[1] + look.rect[3]));
    ASSERT_GT(y1 - y0, 100) << "the canvas is off the screenshot";
    double sx = 0.0, sy = 0.0, n = 0.0, sum = 0.0, sum2 = 0.0;
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) {
        const unsigned char* px =
            &screen.rgb[3 * (static_cast<size_t>(y) * screen.width + static_cast<size_t>(x))];
        const double grey = (px[0] + px[1] + px[2]) / 3.0;
        sum += grey;
        sum2 += grey * grey;
        if (px[0] > 200 && px[1] < 90 && px[2] > 200) {
          sx += x + 0.5;
          sy += y + 0.5;
          n += 1.0;
        }
      }
    const double pixels = static_cast<double>((x1 - x0) * (y1 - y0));
    const double variance = sum2 / pixels - (sum / pixels) * (sum / pixels);
    EXPECT_GT(variance, 20.0) << "the canvas is (nearly) blank";
    ASSERT_GT(n, 4.0) << "no marker on the screen";
    const Eigen::Vector2d seen(sx / n, sy / n);
    const Eigen::Vector2d expected = expected_pixel(file, csv, rows[k], look);
    std::printf(
        "%s at t = %s: marker drawn at (%.1f, %.1f), the CSV's point at (%.1f, %.1f): "
        "%.2f px apart\n",
        c.name, hashes[k], seen.x(), seen.y(), expected.x(), expected.y(),
        (seen - expected).norm());
    EXPECT_LE((seen - expected).norm(), 5.0)
        << "marker drawn at (" << seen.x() << ", " << seen.y() << "), the CSV puts it at ("
        << expected.x() << ", " << expected.y() << ")";
  }
#endif
}

// run --report keeps the whole run to draw it: the options that feed, pace,
// stream or checkpoint a run are refused, naming the option; without them it
// writes the page and the run's CSV.
TEST(RunReport, RefusesTheOptionsOfAStreamedRunAndWritesThePageAndTheCsv) {
  const fs::path dir = scratch_dir("run-report");
  const std::string model = shipped_model("fourbar.yaml");
  for (const std::pair<const char*, const char*>& refused :
       {std::pair<const char*, const char*>{"--out x.csv", "--out"},
        {"--stream", "--stream"},
        {"--real-time", "--real-time"},
        {"--output-interval 0.01", "--output-interval"}}) {
    const CliResult r = run_cli("run " + model + " --report " + dir.string() + " " + refused.first);
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_NE(r.output.find(std::string("run --report takes no ") + refused.second),
              std::string::npos)
        << r.output;
  }
  const CliResult r =
      run_cli("run " + model + " --t-end 1 --formulation penalty --report " + dir.string());
  ASSERT_EQ(r.code, 0) << r.output;
  const std::string html = read_text(dir / "report.html");
  EXPECT_NE(html.find("<title>monohydra run: fourbar</title>"), std::string::npos);
  EXPECT_NE(html.find("formulations: penalty"), std::string::npos);
  const Csv csv = read_csv(dir / "penalty.csv");
  EXPECT_NEAR(csv["t"].back(), 1.0, 1e-9);
}

INSTANTIATE_TEST_SUITE_P(
    Reports, ReportView,
    ::testing::Values(Case{"fourbar", "compare --formulations double-step,penalty", "fourbar.yaml",
                           "double-step.csv"},
                      Case{"excavator", "run", "excavator.yaml", "double-step.csv"}),
    [](const ::testing::TestParamInfo<Case>& param) { return std::string(param.param.name); });

}  // namespace
}  // namespace mh::test
