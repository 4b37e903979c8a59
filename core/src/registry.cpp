#include "geobrush/registry.hpp"

#include <dlfcn.h>

#include <QLibrary>
#include <algorithm>
#include <cstdlib>
#include <set>

namespace geobrush {
namespace {

using AbiVersionFn = int (*)();
using RegisterFn = void (*)(PluginRegistrar&);

void checkPorts(const NodeType& type, const std::vector<PortDecl>& ports, const char* what) {
  std::set<std::string> names;
  for (const auto& port : ports) {
    if (port.name.empty() || port.name.find('.') != std::string::npos)
      throw RegistryError(type.id + ": " + what + " port name '" + port.name +
                          "' must be non-empty and contain no '.'");
    if (!names.insert(port.name).second)
      throw RegistryError(type.id + ": duplicate " + what + " port '" + port.name + "'");
    if (port.typeId.empty())
      throw RegistryError(type.id + ": " + what + " port '" + port.name + "' has no value type");
    if (port.doc.empty())
      throw RegistryError(type.id + ": " + what + " port '" + port.name + "' has no doc");
  }
}

void checkDeclaration(const NodeType& type) {
  if (type.id.empty() || type.id.find('.') == std::string::npos)
    throw RegistryError("node type id '" + type.id + "' must look like 'vendor.name'");
  if (type.version < 1) throw RegistryError(type.id + ": typeVersion must be >= 1");
  if (type.doc.empty()) throw RegistryError(type.id + ": has no doc");
  if (!type.create) throw RegistryError(type.id + ": has no compute function");
  checkPorts(type, type.inputs, "input");
  checkPorts(type, type.outputs, "output");
  std::set<std::string> names;
  for (const auto& param : type.params) {
    if (param.name.empty() || !names.insert(param.name).second)
      throw RegistryError(type.id + ": empty or duplicate param name '" + param.name + "'");
    if (param.doc.empty()) throw RegistryError(type.id + ": param '" + param.name + "' has no doc");
    if (auto error = checkParam(param, param.defaultValue))
      throw RegistryError(type.id + ": default of param '" + param.name + "': " + *error);
  }
  for (const auto& [from, fn] : type.upgrades) {
    if (from < 1 || from >= type.version || !fn)
      throw RegistryError(type.id + ": upgrade from version " + std::to_string(from) +
                          " is not below the type version " + std::to_string(type.version));
  }
}

}  // namespace

struct NodeRegistry::Loaded {
  std::filesystem::path path;
  std::unique_ptr<QLibrary> library;
};

NodeRegistry::NodeRegistry() = default;
// Plugin libraries stay loaded until exit: values and nodes they created may
// outlive the registry, and unloading would leave them without code. Only
// QLibrary::unload() unloads; its destructor leaves the library loaded.
NodeRegistry::~NodeRegistry() = default;

void NodeRegistry::add(NodeType type) {
  checkDeclaration(type);
  if (const NodeType* existing = find(type.id)) {
    throw RegistryError("node type '" + type.id + "' is provided twice: by " +
                        (existing->library.empty() ? "the host" : existing->library) + " and by " +
                        (type.library.empty() ? "the host" : type.library));
  }
  auto it = std::lower_bound(types_.begin(), types_.end(), type.id,
                             [](const auto& t, const std::string& id) { return t->id < id; });
  types_.insert(it, std::make_unique<NodeType>(std::move(type)));
}

const NodeType* NodeRegistry::find(std::string_view id) const {
  auto it = std::lower_bound(types_.begin(), types_.end(), id,
                             [](const auto& t, std::string_view key) { return t->id < key; });
  return (it != types_.end() && (*it)->id == id) ? it->get() : nullptr;
}

std::vector<const NodeType*> NodeRegistry::types() const {
  std::vector<const NodeType*> result;
  for (const auto& type : types_)
    result.push_back(type.get());
  return result;
}

void NodeRegistry::loadPlugin(const std::filesystem::path& file) {
  const std::string name = file.string();
  auto library = std::make_unique<QLibrary>(QString::fromStdString(name));
  // Resolve everything now, so a library with missing symbols fails here and
  // not later in the middle of an evaluation.
  library->setLoadHints(QLibrary::ResolveAllSymbolsHint);
  if (!library->load())
    throw RegistryError(name + ": cannot load plugin: " + library->errorString().toStdString());

  auto abi = reinterpret_cast<AbiVersionFn>(library->resolve("geobrush_plugin_abi_version"));
  auto registerTypes = reinterpret_cast<RegisterFn>(library->resolve("geobrush_plugin_register"));
  if (!abi || !registerTypes) {
    library->unload();
    throw RegistryError(name + ": not a GeoBrush plugin (no GEOBRUSH_PLUGIN entry points)");
  }
  if (int version = abi(); version != kPluginAbiVersion) {
    library->unload();
    throw RegistryError(name + ": built for plugin ABI " + std::to_string(version) +
                        ", this GeoBrush has ABI " + std::to_string(kPluginAbiVersion) +
                        "; rebuild the plugin against this version");
  }

  std::vector<NodeType> declared;
  std::string failure;
  try {
    PluginRegistrar registrar(declared);
    registerTypes(registrar);
    if (declared.empty()) failure = "declares no node type";
    std::set<std::string> ids;
    for (auto& type : declared) {
      type.library = name;
      checkDeclaration(type);
      if (!ids.insert(type.id).second) failure = "declares '" + type.id + "' twice";
      if (const NodeType* existing = find(type.id))
        failure = "node type '" + type.id + "' is already provided by " + existing->library;
    }
  } catch (const std::exception& e) {
    failure = e.what();
  } catch (...) {
    failure = "registration threw an unknown exception";
  }
  if (!failure.empty()) {
    declared.clear();  // drop objects whose code lives in the library first
    library->unload();
    throw RegistryError(name + ": plugin refused: " + failure);
  }
  for (auto& type : declared)
    add(std::move(type));
  libraries_.push_back(std::make_unique<Loaded>(Loaded{file, std::move(library)}));
}

NodeRegistry::LoadReport NodeRegistry::loadPlugins(const std::vector<std::filesystem::path>& dirs) {
  LoadReport report;
  std::set<std::filesystem::path> seen;
  for (const auto& loaded : libraries_)
    seen.insert(loaded->path);
  for (const auto& dir : dirs) {
    searchedDirs_.push_back(dir);
    std::error_code ec;
    if (!std::filesystem::is_directory(dir, ec)) continue;
    std::vector<std::filesystem::path> files;
    for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
      if (entry.path().extension() == ".so") files.push_back(entry.path());
    }
    std::sort(files.begin(), files.end());
    for (const auto& file : files) {
      auto canonical = std::filesystem::weakly_canonical(file, ec);
      if (!seen.insert(canonical).second) continue;
      try {
        loadPlugin(canonical);
        report.loaded.push_back(canonical);
      } catch (const std::exception& e) {
        report.errors.push_back(e.what());
        refusals_[canonical.filename().string()] = e.what();
      }
    }
  }
  return report;
}

std::optional<std::string> NodeRegistry::refusal(const std::string& fileName) const {
  auto it = refusals_.find(fileName);
  if (it == refusals_.end()) return std::nullopt;
  return it->second;
}

std::vector<std::filesystem::path> defaultPluginDirs() {
  std::vector<std::filesystem::path> dirs;
  if (auto lib = coreLibraryDir(); !lib.empty()) dirs.push_back(lib / "geobrush" / "plugins");
  if (const char* extra = std::getenv("GEOBRUSH_PLUGIN_PATH")) {
    std::string list = extra;
    std::size_t start = 0;
    while (start <= list.size()) {
      std::size_t colon = std::min(list.find(':', start), list.size());
      if (colon > start) dirs.emplace_back(list.substr(start, colon - start));
      start = colon + 1;
    }
  }
  return dirs;
}

std::filesystem::path coreLibraryDir() {
  Dl_info info{};
  if (!::dladdr(reinterpret_cast<const void*>(&coreLibraryDir), &info) || !info.dli_fname)
    return {};
  std::error_code ec;
  const auto library = std::filesystem::canonical(info.dli_fname, ec);
  return ec ? std::filesystem::path() : library.parent_path();
}

std::string expectedPluginFile(std::string_view typeId) {
  std::string name(typeId);
  std::replace(name.begin(), name.end(), '.', '_');
  return name + ".so";
}

}  // namespace geobrush
