// Wavefront OBJ: "v x y z" vertices and "f i j k ..." faces; everything else is skipped.
#include "geobrush/text.hpp"
#include "mesh_read.hpp"

namespace geobrush::meshread {

PolygonSoup readObj(const Source& source) {
  PolygonSoup soup;
  LineReader lines(source.bytes);
  std::string_view line;
  while (lines.nextData(line)) {
    std::string_view rest = line;
    const auto keyword = nextToken(rest);
    const auto where = [&] { return "line " + std::to_string(lines.number()) + ": "; };
    if (keyword == "v") {
      const auto point = parsePoint(rest);
      if (!point) throw source.error(where() + "a vertex needs three numbers: " + quoteText(line));
      if (!isFinite(*point))
        throw source.nonFinite("vertex", soup.points.size(), lines.number(), quoteText(line));
      soup.points.push_back(*point);
    } else if (keyword == "f") {
      for (auto token = nextToken(rest); !token.empty(); token = nextToken(rest)) {
        // "i", "i/t", "i//n" or "i/t/n": the texture and normal indices are not read.
        const auto index = parseInteger(token.substr(0, token.find('/')));
        if (!index || token.starts_with('+'))
          throw source.error(where() + quoteText(token) + " is not a vertex index");
        // 1-based, or counted back from the last vertex so far when negative; 0 names none.
        const auto size = static_cast<long long>(soup.points.size());
        soup.addCorner(*index < 0 ? size + *index : *index - 1);
      }
      soup.endPolygon();
    }
  }
  return soup;
}

}  // namespace geobrush::meshread
