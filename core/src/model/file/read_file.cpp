// Reading a model file: the checks before parsing (a regular text file of at
// most 64 MiB, no NUL byte, ending with a line break, one YAML document), the
// entry points load_model_file and parse_model_text, and the top-level mapping
// that hands each section to its reader.
#include <yaml-cpp/eventhandler.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <system_error>

#include "monohydra/core/model_text.hpp"
#include "parser.hpp"

namespace mh {

namespace fs = std::filesystem;

namespace model_file_detail {

ModelFile Parser::parse(const YAML::Node& root, const std::string& base_dir) {
  if (!root.IsMap()) {
    fail(root, "", "expected a mapping with the model (units, bodies, ...), got " + describe(root));
  }
  const MapView top(*this, root, "",
                    {"units", "name", "gravity", "plugin_paths", "plugins", "bodies", "cut_joints",
                     "subsystems", "formulation", "integrator", "compare", "solver", "planar",
                     "assembly", "nodes", "equilibrium", "output", "inputs", "sensors"});
  ModelFile file;
  file.path = file_;
  {
    std::error_code ec;
    const fs::path base = fs::absolute(fs::path(base_dir.empty() ? "." : base_dir), ec);
    file.folder = (ec ? fs::path(base_dir) : base).lexically_normal().string();
    while (file.folder.size() > 1 && file.folder.back() == '/') file.folder.pop_back();
  }

  parse_units(top);

  if (auto name_node = top.get("name")) {
    file.model.name = name(*name_node, "name");
  } else {
    file.model.name = fs::path(file_).stem().string();
  }
  if (auto gravity = top.get("gravity")) {
    file.model.gravity = vector3(*gravity, "gravity");
    for (std::size_t i = 0; i < 3; ++i)
      bounded(file.model.gravity[static_cast<Eigen::Index>(i)], (*gravity)[i],
              index_field("gravity", i), kMaxGravity, "m/s^2");
  }
  if (auto paths = top.get("plugin_paths")) file.plugin_paths = plugin_paths(*paths, base_dir);
  if (auto chosen = top.get("plugins")) file.plugin_libraries = plugin_libraries(*chosen, base_dir);

  // A model of subsystems only (an imported FMU, a signal chain) has no
  // mechanism: no bodies key is an empty one. A model with neither has nothing
  // to simulate.
  if (auto bodies_node = top.get("bodies")) {
    parse_bodies(*bodies_node, file);
  } else if (!top.get("subsystems")) {
    fail(root, "bodies",
         "expected bodies: (a list of bodies, may be empty) or subsystems: (a model of "
         "subsystems only), found neither");
  } else {
    parse_bodies(YAML::Node(YAML::NodeType::Sequence), file);
  }

  if (auto planar_node = top.get("planar")) {
    file.model.planar = boolean(*planar_node, "planar");
    if (file.model.planar) check_planar(file);
  }
  if (auto cuts = top.get("cut_joints")) file.model.cut_joints = cut_joints(*cuts);
  if (auto assembly_node = top.get("assembly")) parse_assembly(*assembly_node, file);
  if (auto inputs_node = top.get("inputs")) file.inputs = inputs(*inputs_node);
  std::map<std::string, SourceMark> columns;
  if (auto subsystems_node = top.get("subsystems"))
    file.subsystems = subsystems(*subsystems_node, columns);
  if (auto nodes_node = top.get("nodes")) parse_nodes(*nodes_node, file, columns);
  check_node_columns(file);
  if (auto equilibrium_node = top.get("equilibrium")) parse_equilibrium(*equilibrium_node, file);

  file.formulation.mark = mark(root);
  if (auto formulation_node = top.get("formulation")) {
    file.formulation = component_choice(*formulation_node, "formulation", kDefaultFormulation);
  }
  file.integrator.mark = mark(root);
  if (auto integrator_node = top.get("integrator")) {
    file.integrator = component_choice(*integrator_node, "integrator", kDefaultIntegrator);
  }
  if (auto compare_node = top.get("compare")) parse_compare(*compare_node, file);
  file.output.mark = mark(root);
  if (auto output_node = top.get("output")) file.output = output(*output_node);
  if (auto sensors_node = top.get("sensors")) file.sensors = sensors(*sensors_node);
  file.solver.mark = mark(root);
  if (auto solver_node = top.get("solver")) file.solver = solver(*solver_node);
  return file;
}

std::vector<std::string> Parser::plugin_paths(const YAML::Node& node,
                                              const std::string& base_dir) const {
  if (!node.IsSequence()) {
    fail(node, "plugin_paths", "expected a list of folders, got " + describe(node));
  }
  std::vector<std::string> paths;
  std::error_code ec;
  fs::path base = fs::absolute(fs::path(base_dir.empty() ? "." : base_dir), ec);
  if (ec) base = fs::path(base_dir);
  for (std::size_t i = 0; i < node.size(); ++i) {
    const std::string field = index_field("plugin_paths", i);
    const std::string text = string(node[i], field);
    if (text.empty()) fail(node[i], field, "expected a non-empty folder path");
    fs::path path(text);
    if (path.is_relative()) path = base / path;
    paths.push_back(path.lexically_normal().string());
  }
  return paths;
}

// plugins: {ID: LIBRARY.so}: which library a component id comes from when
// several offer it; relative files against the model file's folder.
std::map<std::string, std::string> Parser::plugin_libraries(const YAML::Node& node,
                                                            const std::string& base_dir) const {
  if (!node.IsMap()) {
    fail(node, "plugins",
         "expected a mapping from component id to library file ({penalty: lib/penalty.so}), got " +
             describe(node));
  }
  const MapView map(*this, node, "plugins", {});
  std::map<std::string, std::string> libraries;
  std::error_code ec;
  fs::path base = fs::absolute(fs::path(base_dir.empty() ? "." : base_dir), ec);
  if (ec) base = fs::path(base_dir);
  for (const Entry& e : map.entries()) {
    const std::string field = map.field(e.key);
    const std::string text = string(e.value, field);
    if (text.empty()) fail(e.value, field, "expected the path of a plugin library (.so)");
    fs::path path(text);
    if (path.is_relative()) path = base / path;
    libraries[e.key] = path.lexically_normal().string();
  }
  return libraries;
}

}  // namespace model_file_detail

namespace {
constexpr std::uintmax_t kMaxFileBytes = 64u << 20;

// Where a document's first content is, if it has any. yaml-cpp 0.7's LoadAll
// never returns on a stray top-level ',' (its parser yields empty documents
// forever without consuming it; found by tests/fuzz), so documents are read
// one at a time and only the first two are looked at.
class FirstContent : public YAML::EventHandler {
 public:
  std::optional<YAML::Mark> mark;
  void OnDocumentStart(const YAML::Mark&) override {}
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark&, YAML::anchor_t) override {}
  void OnAlias(const YAML::Mark& m, YAML::anchor_t) override { see(m); }
  void OnScalar(const YAML::Mark& m, const std::string&, YAML::anchor_t,
                const std::string&) override {
    see(m);
  }
  void OnSequenceStart(const YAML::Mark& m, const std::string&, YAML::anchor_t,
                       YAML::EmitterStyle::value) override {
    see(m);
  }
  void OnSequenceEnd() override {}
  void OnMapStart(const YAML::Mark& m, const std::string&, YAML::anchor_t,
                  YAML::EmitterStyle::value) override {
    see(m);
  }
  void OnMapEnd() override {}

 private:
  void see(const YAML::Mark& m) {
    if (!mark) mark = m;
  }
};

SourceMark source_mark(const std::string& file, const YAML::Mark& m) {
  SourceMark mark;
  mark.file = file;
  if (!m.is_null() && m.line >= 0) {
    mark.line = m.line + 1;
    mark.column = m.column >= 0 ? m.column + 1 : 0;
  }
  return mark;
}
}  // namespace

ModelFile parse_model_text(const std::string& yaml_text, const std::string& file_label,
                           const std::string& base_dir) {
  YAML::Node root;
  try {
    std::istringstream in(yaml_text);
    YAML::Parser reader(in);
    FirstContent first, second;
    if (reader.HandleNextDocument(first) && reader.HandleNextDocument(second) && second.mark)
      throw InputError(source_mark(file_label, *second.mark), "",
                       "expected a single YAML document, found more than one");
    root = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    throw InputError(source_mark(file_label, e.mark), "", "malformed YAML: " + e.msg);
  }
  model_file_detail::Parser parser(file_label);
  return parser.parse(root, base_dir);
}

// A model file is a regular text file of at most 64 MiB that ends with a line
// break: /dev/zero, a FIFO or a binary are refused before yaml-cpp reads them
// (it would grow without bound), and a file cut mid-line is caught.
std::string read_model_text(const std::string& path) {
  SourceMark mark;
  mark.file = path;
  std::error_code ec;
  const fs::path file(path);
  if (!fs::exists(file, ec)) throw InputError(mark, "", "cannot open the model file: no such file");
  if (fs::is_directory(file, ec)) {
    throw InputError(mark, "", "cannot open the model file: it is a folder");
  }
  if (!fs::is_regular_file(file, ec)) {
    throw InputError(mark, "",
                     "cannot read the model file: not a regular file (a device, FIFO or socket)");
  }
  const std::uintmax_t size = fs::file_size(file, ec);
  if (ec || size > kMaxFileBytes) {
    throw InputError(mark, "",
                     "the model file is " + std::to_string(size) +
                         " bytes, above the limit of 67108864 bytes (64 MiB)");
  }
  std::ifstream in(file, std::ios::binary);
  if (!in) {
    throw InputError(mark, "", std::string("cannot open the model file: ") + std::strerror(errno));
  }
  // One byte more than its size, to notice a file that grows while read.
  std::string text(static_cast<std::size_t>(size) + 1, '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  if (in.bad()) throw InputError(mark, "", "cannot read the model file");
  text.resize(static_cast<std::size_t>(in.gcount()));
  if (text.size() > size) throw InputError(mark, "", "the model file changed while being read");
  if (const auto nul = text.find('\0'); nul != std::string::npos)
    throw InputError(mark, "",
                     "not a text file: it holds a NUL byte at offset " + std::to_string(nul));
  if (!text.empty() && text.back() != '\n') {
    mark.line = static_cast<int>(std::count(text.begin(), text.end(), '\n')) + 1;
    throw InputError(mark, "",
                     "the file does not end with a line break, so it may have been cut short "
                     "(end its last line with one)");
  }
  return text;
}

ModelFile load_model_file(const std::string& path) {
  fs::path base = fs::path(path).parent_path();
  if (base.empty()) base = ".";
  return parse_model_text(read_model_text(path), path, base.string());
}

}  // namespace mh
