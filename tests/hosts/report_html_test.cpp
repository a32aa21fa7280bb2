// The report `monohydra compare --report` writes: every figure of the
// paper's Sect. 6 is in it, it and each SVG are well-formed XML (xmllint),
// it needs no network, and Chromium renders it (a headless screenshot that
// shows the plots' colours). Its 3D view: report_view_test.cpp.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "cli_runner.hpp"
#include "report_figures.hpp"

#ifdef MH_HAVE_LIBPNG
#include <png.h>
#endif

namespace mh::test {
namespace {

namespace fs = std::filesystem;

// One comparison on the quick-return, 2.5 s (frames at 0, 1 and 2 s), shared
// by the tests below.
class Report : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new fs::path(scratch_dir("report"));
    result_ = new CliResult(run_cli("compare " + shipped_model("quickreturn-free.yaml") +
                                    " --formulations double-step,penalty --t-end 2.5 --report " +
                                    dir_->string()));
  }
  static void TearDownTestSuite() {
    delete dir_;
    delete result_;
  }
  static std::string html() { return read_text(*dir_ / "report.html"); }
  // The text of <figure id="ID"> .. </figure>.
  static std::string figure(const std::string& id) {
    const std::string text = html();
    const size_t begin = text.find("<figure id=\"" + id + "\">");
    if (begin == std::string::npos) return "";
    return text.substr(begin, text.find("</figure>", begin) - begin);
  }
  static size_t count(const std::string& text, const std::string& what) {
    size_t n = 0;
    for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
    return n;
  }
  static fs::path* dir_;
  static CliResult* result_;
};
fs::path* Report::dir_ = nullptr;
CliResult* Report::result_ = nullptr;

TEST_F(Report, HoldsEveryFigureOfSection6) {
  ASSERT_EQ(result_->code, 0) << result_->output;
  for (const auto& id : mh::cli::report_figure_ids()) {
    const std::string f = figure(id);
    ASSERT_FALSE(f.empty()) << id;
    if (id == "fig-pressures") {
      // The free mechanism has no pressures: the panel says so.
      EXPECT_NE(f.find("class=\"omitted\""), std::string::npos);
      EXPECT_NE(f.find("no pressures"), std::string::npos);
      continue;
    }
    if (id == "fig-actuators") {
      // Nor outputs in m, N or W: no actuator panel either.
      EXPECT_NE(f.find("class=\"omitted\""), std::string::npos);
      EXPECT_NE(f.find("no outputs in m, N or W"), std::string::npos);
      continue;
    }
    if (id == "fig-dissipation") {
      // Nor a subsystem that dissipates.
      EXPECT_NE(f.find("class=\"omitted\""), std::string::npos);
      EXPECT_NE(f.find("reports a dissipation"), std::string::npos);
      continue;
    }
    EXPECT_EQ(count(f, "<svg xmlns=\"http://www.w3.org/2000/svg\""), 1u) << id;
  }
  // Fig. 6: the mechanism at t = 0, 1 and 2 s, all five bodies each time.
  const std::string mech = figure("fig-mechanism");
  EXPECT_EQ(count(mech, "<g class=\"frame\""), 3u);
  for (const char* t : {"data-t=\"0\"", "data-t=\"1\"", "data-t=\"2\""})
    EXPECT_NE(mech.find(t), std::string::npos) << t;
  EXPECT_EQ(count(mech, "class=\"joint\""), 3u * 5u);
  EXPECT_EQ(count(mech, "class=\"guide\""), 1u);  // the ram's ground guide Y = 5
  // Figs. 7a-8a: five coordinates for each of the two formulations.
  EXPECT_EQ(count(figure("fig-coordinates"), "class=\"series\""), 10u);
  // Figs. 9-10: KE, PE and W of each run; drift of each run.
  EXPECT_EQ(count(figure("fig-energies"), "class=\"series\""), 6u);
  EXPECT_EQ(count(figure("fig-drift"), "class=\"series\""), 2u);
  EXPECT_EQ(count(figure("fig-constraints"), "class=\"series\""), 2u);
  EXPECT_EQ(count(figure("fig-iterations"), "class=\"series\""), 2u);
  EXPECT_EQ(count(figure("fig-step-time"), "class=\"series\""), 2u);
  // No control signal in this model: nothing shaded, and the report says why.
  EXPECT_EQ(count(html(), "class=\"shade\""), 0u);
  EXPECT_NE(html().find("control signals: the model declares none"), std::string::npos);
  // Each run's CSV beside it, linked.
  for (const char* csv : {"double-step.csv", "penalty.csv"}) {
    EXPECT_TRUE(fs::exists(*dir_ / csv));
    EXPECT_NE(html().find(std::string("<a href=\"") + csv + "\">"), std::string::npos);
  }
}

// The page loads nothing: its scripts (three.js, the 3D view and its frames)
// are inline, no element names a source, and the only URLs outside the
// scripts are the XML namespaces. (That the page requests nothing when it
// runs is report_view_test's, in Chromium with the network cut.)
TEST_F(Report, NeedsNoNetwork) {
  std::string text = html();
  const bool view = text.find("id=\"mh-view-canvas\"") != std::string::npos;  // built with three.js
  size_t scripts = 0;
  for (size_t at = text.find("<script"); at != std::string::npos; at = text.find("<script", at)) {
    const size_t open_end = text.find('>', at);
    ASSERT_NE(open_end, std::string::npos);
    EXPECT_EQ(text.substr(at, open_end - at), "<script") << "a script with attributes (src?)";
    const size_t close = text.find("</script>", open_end);
    ASSERT_NE(close, std::string::npos);
    text.erase(at, close + 9 - at);  // what remains is the markup
    ++scripts;
  }
  EXPECT_EQ(scripts, view ? 4u : 0u) << "three.js, OrbitControls, the frames and the view";
  EXPECT_EQ(text.find("<link"), std::string::npos);
  EXPECT_EQ(text.find("src="), std::string::npos);
  EXPECT_EQ(text.find("<iframe"), std::string::npos);
  for (size_t at = text.find("url("); at != std::string::npos; at = text.find("url(", at + 4))
    EXPECT_EQ(text.compare(at, 5, "url(#"), 0) << "only references within the page";
  // The only URLs are the namespaces; links are relative. (A plain search,
  // not std::regex: GCC 12 warns -Wmaybe-uninitialized inside libstdc++'s
  // regex automaton in the sanitizer build, a false positive.)
  size_t urls = 0;
  for (size_t at = text.find("://"); at != std::string::npos; at = text.find("://", at + 3)) {
    const bool http = at >= 4 && text.compare(at - 4, 4, "http") == 0;
    const bool https = at >= 5 && text.compare(at - 5, 5, "https") == 0;
    EXPECT_TRUE(http || https) << text.substr(at < 8 ? 0 : at - 8, 40);
    const size_t end = text.find('"', at);
    ASSERT_NE(end, std::string::npos) << text.substr(at);
    const std::string where = text.substr(at + 3, end - at - 3);
    EXPECT_TRUE(where == "www.w3.org/1999/xhtml" || where == "www.w3.org/2000/svg") << where;
    ++urls;
  }
  EXPECT_GT(urls, 0u);
}

TEST_F(Report, ReportAndEverySvgAreWellFormedXml) {
  ASSERT_TRUE(have_program("xmllint")) << "install libxml2-utils (bash .ci/setup does)";
  const CliResult page = run_shell("xmllint --noout '" + (*dir_ / "report.html").string() + "'");
  EXPECT_EQ(page.code, 0) << page.output;
  size_t svgs = 0;
  for (const auto& entry : fs::directory_iterator(*dir_ / "figures")) {
    if (entry.path().extension() != ".svg") continue;
    ++svgs;
    const CliResult r = run_shell("xmllint --noout '" + entry.path().string() + "'");
    EXPECT_EQ(r.code, 0) << entry.path() << "\n" << r.output;
    // The figure is the same in the page.
    const std::string svg = read_text(entry.path());
    EXPECT_NE(html().find(svg.substr(svg.find("<svg"))), std::string::npos) << entry.path();
  }
  EXPECT_EQ(svgs, 7u);  // every figure but the pressures
}

#ifdef MH_HAVE_LIBPNG
// Pixels of an RGB screenshot within `tolerance` of a colour 0xrrggbb.
size_t pixels_near(const std::vector<unsigned char>& rgb, unsigned colour, int tolerance) {
  const int r = (colour >> 16) & 0xff, g = (colour >> 8) & 0xff, b = colour & 0xff;
  size_t n = 0;
  for (size_t i = 0; i + 2 < rgb.size(); i += 3)
    if (std::abs(rgb[i] - r) <= tolerance && std::abs(rgb[i + 1] - g) <= tolerance &&
        std::abs(rgb[i + 2] - b) <= tolerance)
      ++n;
  return n;
}
#endif

TEST_F(Report, ChromiumRendersThePlots) {
  if (!have_program("chromium")) GTEST_SKIP() << "chromium is not installed";
#ifndef MH_HAVE_LIBPNG
  GTEST_SKIP() << "built without libpng: cannot read the screenshot";
#else
  const fs::path png = *dir_ / "screenshot.png";
  const CliResult shot = run_shell(
      "chromium --headless --no-sandbox --disable-gpu --hide-scrollbars --screenshot='" +
      png.string() + "' --window-size=1200,4000 'file://" + (*dir_ / "report.html").string() + "'");
  ASSERT_TRUE(fs::exists(png)) << shot.output;
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  ASSERT_NE(png_image_begin_read_from_file(&image, png.string().c_str()), 0) << image.message;
  image.format = PNG_FORMAT_RGB;
  std::vector<unsigned char> rgb(PNG_IMAGE_SIZE(image));
  ASSERT_NE(png_image_finish_read(&image, nullptr, rgb.data(), 0, nullptr), 0) << image.message;
  EXPECT_EQ(image.width, 1200u);
  EXPECT_EQ(image.height, 4000u);
  const size_t pixels = static_cast<size_t>(image.width) * image.height;
  const size_t white = pixels_near(rgb, 0xffffff, 4);
  EXPECT_GT(pixels - white, pixels / 50) << "the page is (nearly) blank";
  // The series' colours are on screen: the plots were drawn, not just text.
  EXPECT_GT(pixels_near(rgb, 0x4e79a7, 40), 2000u) << "first formulation's lines";
  EXPECT_GT(pixels_near(rgb, 0xf28e2b, 40), 1000u) << "second formulation's lines";
  EXPECT_GT(pixels_near(rgb, 0x1f3b73, 30), 200u) << "the mechanism's last frame";
#endif
}

}  // namespace
}  // namespace mh::test
