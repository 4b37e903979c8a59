// JSON output of the CLI; the only CLI file that sees nlohmann_json.
#include <nlohmann/json.hpp>

#include "commands.hpp"

namespace geobrush::cli {
namespace {

using nlohmann::json;

json paramValueJson(const ParamValue& value) {
  return std::visit(
      [](const auto& v) -> json {
        using T = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<T, Vec3>)
          return json::array({v[0], v[1], v[2]});
        else
          return v;
      },
      value);
}

json portsJson(const std::vector<PortDecl>& ports) {
  json list = json::array();
  for (const auto& port : ports)
    list.push_back({{"name", port.name},
                    {"type", port.typeId},
                    {"doc", port.doc},
                    {"optional", port.optional}});
  return list;
}

json runReport(const std::filesystem::path& graph, const EvalReport& report,
               const std::vector<std::string>& pluginErrors,
               const std::map<std::string, double>& metrics) {
  json nodes = json::array();
  for (const auto& run : report.runs) {
    nodes.push_back({{"name", run.node},
                     {"type", run.type},
                     {"key", toHex(run.key)},
                     {"seconds", run.seconds},
                     {"cacheHit", run.cacheHit},
                     {"failed", run.failed},
                     {"warnings", run.warnings}});
  }
  json outputs = json::array();
  for (const auto& file : report.filesWritten)
    outputs.push_back(file.string());
  json root = {{"graph", graph.string()},
               {"ok", report.ok},
               {"outputs", outputs},
               {"nodes", nodes},
               {"computed", report.computed()},
               {"cacheHits", report.cacheHits()},
               {"pluginErrors", pluginErrors}};
  if (!report.ok) root["error"] = report.error;
  if (!metrics.empty()) root["metrics"] = metrics;
  return root;
}

std::string text(const json& root) {
  return root.dump(2, ' ', false, json::error_handler_t::replace) + "\n";
}

}  // namespace

std::string runReportJson(const std::filesystem::path& graph, const EvalReport& report,
                          const std::vector<std::string>& pluginErrors,
                          const std::map<std::string, double>& metrics) {
  return text(runReport(graph, report, pluginErrors, metrics));
}

std::string fillReportJson(const std::filesystem::path& mesh, const EvalReport& report,
                           const std::vector<std::string>& pluginErrors,
                           const std::map<std::string, double>& metrics,
                           const std::vector<std::string>& notes) {
  json root = runReport(mesh, report, pluginErrors, metrics);
  // fill.loop.N.FIELD, one object per loop in order.
  const std::string prefix = "fill.loop.";
  std::map<int, json> loops;
  for (const auto& [key, value] : metrics) {
    if (key.rfind(prefix, 0) != 0) continue;
    const auto dot = key.find('.', prefix.size());
    if (dot == std::string::npos) continue;
    const int id = std::stoi(key.substr(prefix.size(), dot - prefix.size()));
    const std::string field = key.substr(dot + 1);
    json& loop = loops[id];
    loop["loop"] = id;
    if (field == "filled")
      loop[field] = value != 0.0;
    else if (field == "border_edges" || field == "new_vertices" || field == "new_faces" ||
             field == "continuity")
      loop[field] = int(value);
    else
      loop[field] = value;
  }
  json holes = json::array();
  for (auto& [id, loop] : loops)
    holes.push_back(std::move(loop));
  root["holes"] = std::move(holes);
  root["notes"] = notes;
  return text(root);
}

std::string nodeTypesJson(const NodeRegistry& registry) {
  json types = json::array();
  for (const NodeType* type : registry.types()) {
    json params = json::array();
    for (const auto& param : type->params) {
      json entry = {{"name", param.name},
                    {"kind", std::string(toString(param.kind))},
                    {"default", paramValueJson(param.defaultValue)},
                    {"doc", param.doc}};
      if (param.min) entry["min"] = *param.min;
      if (param.max) entry["max"] = *param.max;
      if (!param.choices.empty()) entry["choices"] = param.choices;
      if (param.kind == ParamKind::DoubleList) entry["rowSize"] = param.rowSize;
      params.push_back(entry);
    }
    types.push_back({{"id", type->id},
                     {"version", type->version},
                     {"label", type->label},
                     {"category", type->category},
                     {"doc", type->doc},
                     {"library", type->library},
                     {"inputs", portsJson(type->inputs)},
                     {"outputs", portsJson(type->outputs)},
                     {"params", params}});
  }
  return json(types).dump(2, ' ', false, json::error_handler_t::replace) + "\n";
}

std::string compareReportJson(const ComparedGraph& a, const ComparedGraph& b,
                              const std::filesystem::path& image, const std::string& error) {
  auto side = [](const ComparedGraph& g) {
    json times = json::object();
    for (const auto& run : g.report.runs)
      times[run.node] = run.seconds;
    json result = {{"graph", g.graph.string()},
                   {"ok", g.report.ok},
                   {"metrics", g.metrics},
                   {"notes", g.notes},
                   {"seconds", times}};
    if (!g.report.ok) result["error"] = g.report.error;
    return result;
  };
  json better = json::object();
  for (const auto* metrics : {&a.metrics, &b.metrics})
    for (const auto& [key, value] : *metrics)
      if (const std::string which = betterSide(key, a.metrics, b.metrics); !which.empty())
        better[key] = which;
  json root = {{"a", side(a)}, {"b", side(b)}, {"better", better}, {"ok", error.empty()}};
  if (!image.empty()) root["image"] = image.string();
  if (!error.empty()) root["error"] = error;
  return root.dump(2, ' ', false, json::error_handler_t::replace) + "\n";
}

}  // namespace geobrush::cli
