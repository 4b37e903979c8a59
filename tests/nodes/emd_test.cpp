#include "emd.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "canvas_fixtures.hpp"
#include "direct_context.hpp"
#include "geobrush/canvas.hpp"
#include "geobrush/mesh_io.hpp"
#include "geobrush/values.hpp"
#include "geobrush/vertex_fields.hpp"
#include "test_support.hpp"

namespace geobrush {
namespace {

constexpr double kPi = std::numbers::pi;

struct GridSignal {
  MeshPtr grid;
  std::vector<double> fine, coarse;  // the two terms, per vertex
  std::vector<int> interior;         // vertices with |x|, |y| < 0.7
};

// sin sin products of wavelengths `fine` and `coarse` over a flat (n x n)-quad grid of [-1, 1]^2.
GridSignal twoScales(int n, double fineWavelength, double coarseWavelength) {
  GridSignal s;
  s.grid = test::heightGrid(n, [](double, double) { return 0.0; });
  for (auto v : s.grid->surface.vertices()) {
    const auto& p = s.grid->surface.point(v);
    const auto wave = [&](double wavelength) {
      return std::sin(2 * kPi * p[0] / wavelength) * std::sin(2 * kPi * p[1] / wavelength);
    };
    s.fine.push_back(wave(fineWavelength));
    s.coarse.push_back(coarseWavelength > 0 ? wave(coarseWavelength) : 0.0);
    if (std::abs(p[0]) < 0.7 && std::abs(p[1]) < 0.7) s.interior.push_back(v.idx());
  }
  return s;
}

std::vector<double> sum(const std::vector<double>& a, const std::vector<double>& b) {
  std::vector<double> c(a.size());
  for (std::size_t i = 0; i < a.size(); ++i)
    c[i] = a[i] + b[i];
  return c;
}

double correlation(const std::vector<double>& a, const std::vector<double>& b,
                   const std::vector<int>& at) {
  double ab = 0, aa = 0, bb = 0, ma = 0, mb = 0;
  for (int i : at) {
    ma += a[i] / double(at.size());
    mb += b[i] / double(at.size());
  }
  for (int i : at) {
    ab += (a[i] - ma) * (b[i] - mb);
    aa += (a[i] - ma) * (a[i] - ma);
    bb += (b[i] - mb) * (b[i] - mb);
  }
  return ab / std::sqrt(aa * bb);
}

double rms(const std::vector<double>& a, const std::vector<int>& at) {
  double sq = 0;
  for (int i : at)
    sq += a[i] * a[i];
  return std::sqrt(sq / double(at.size()));
}

void expectSumsBack(const EmdResult& result, const std::vector<double>& signal) {
  double scale = 0;
  for (double g : signal)
    scale = std::max(scale, std::abs(g));
  for (std::size_t i = 0; i < signal.size(); ++i) {
    double total = result.residue[i];
    for (const auto& mode : result.modes)
      total += mode[i];
    EXPECT_NEAR(total, signal[i], 1e-12 * std::max(scale, 1.0)) << i;
  }
}

// T2: a fine wave over a coarse one comes apart: h1 is the fine wave, with more extrema than h2.
TEST(Emd, SeparatesTwoScales) {
  const GridSignal s = twoScales(100, 0.2, 1.0);
  const std::vector<double> signal = sum(s.fine, s.coarse);
  for (const Envelope envelope : {Envelope::harmonic, Envelope::biharmonic}) {
    const EmdResult result =
        empiricalModeDecomposition(s.grid->surface, signal, {.envelope = envelope});
    ASSERT_EQ(result.modes.size(), 3u);
    expectSumsBack(result, signal);
    EXPECT_GT(correlation(result.modes[0], s.fine, s.interior), 0.95);
    const auto extremaOf = [&](const std::vector<double>& mode) {
      return localMaxima(s.grid->surface, mode).size() + localMinima(s.grid->surface, mode).size();
    };
    EXPECT_GT(extremaOf(result.modes[0]), extremaOf(result.modes[1]));
    // What is left after h1 is the coarse wave.
    EXPECT_GT(correlation(sum(sum(result.modes[1], result.modes[2]), result.residue), s.coarse,
                          s.interior),
              0.95);
  }
}

// T3: one scale is one mode: h1 is the wave and nothing is left of it in the interior. Both
// envelopes; the report records how far the signal escapes them.
TEST(Emd, TakesASingleScaleWholeIntoTheFirstMode) {
  const GridSignal s = twoScales(60, 0.4, 0.0);
  for (const Envelope envelope : {Envelope::biharmonic, Envelope::harmonic}) {
    const EmdResult result =
        empiricalModeDecomposition(s.grid->surface, s.fine, {.envelope = envelope});
    expectSumsBack(result, s.fine);
    std::vector<double> error(s.fine.size());
    for (std::size_t i = 0; i < error.size(); ++i)
      error[i] = result.modes[0][i] - s.fine[i];
    EXPECT_LT(rms(error, s.interior), 0.05 * rms(s.fine, s.interior));
    std::vector<double> rest = sum(result.modes[1], result.modes[2]);
    rest = sum(rest, result.residue);
    EXPECT_LT(rms(rest, s.interior), 0.05 * rms(s.fine, s.interior));
    EXPECT_GE(result.reports[0].overshoot, 0.0);
    EXPECT_GE(result.reports[0].sifts, 1);
    if (envelope == Envelope::harmonic) {
      EXPECT_LT(result.reports[0].overshoot, 1e-9);
    }
  }
}

// T2: a constant has no extrema but itself; it is all residue.
TEST(Emd, LeavesAConstantInTheResidue) {
  const MeshPtr grid = test::heightGrid(10, [](double, double) { return 0.0; });
  const std::vector<double> constant(grid->surface.n_vertices(), 2.5);
  const EmdResult result = empiricalModeDecomposition(grid->surface, constant, {});
  expectSumsBack(result, constant);
  for (const auto& mode : result.modes)
    for (double h : mode)
      EXPECT_LT(std::abs(h), 1e-12);
}

TEST(Emd, FindsExtremaWithTiesOrderedById) {
  const MeshPtr grid = test::heightGrid(2, [](double, double) { return 0.0; });
  std::vector<double> values(9, 0.0);
  values[4] = 1.0;  // the centre
  EXPECT_EQ(localMaxima(grid->surface, values), std::vector<int>{4});
  // All equal: the lowest id ranks highest among its neighbours, the highest id lowest.
  const std::vector<double> flat(9, 0.0);
  EXPECT_EQ(localMaxima(grid->surface, flat), std::vector<int>{0});
  EXPECT_EQ(localMinima(grid->surface, flat), std::vector<int>{8});
}

TEST(Emd, RefusesBadOptionsAndSignals) {
  const MeshPtr grid = test::heightGrid(4, [](double, double) { return 0.0; });
  const std::vector<double> signal(grid->surface.n_vertices(), 1.0);
  EXPECT_THROW(empiricalModeDecomposition(grid->surface, signal, {.modes = 0}), std::out_of_range);
  EXPECT_THROW(empiricalModeDecomposition(grid->surface, signal, {.sdStop = 0}), std::out_of_range);
  EXPECT_THROW(empiricalModeDecomposition(grid->surface, std::vector<double>(3), {}),
               std::invalid_argument);
  std::vector<double> bad = signal;
  bad[2] = std::nan("");
  EXPECT_THROW(empiricalModeDecomposition(grid->surface, bad, {}), std::invalid_argument);
}

const NodeType& nodeType(const std::string& id) {
  const NodeType* type = test::registry().find(id);
  EXPECT_NE(type, nullptr) << id;
  return *type;
}

std::shared_ptr<const VertexFields> signalOf(const MeshPtr& mesh) {
  test::DirectContext ctx(nodeType("geobrush.emd_signal"), {{"mesh", mesh}});
  nodeType("geobrush.emd_signal").create()->compute(ctx);
  return std::dynamic_pointer_cast<const VertexFields>(ctx.outputs["signal"]);
}

// The node on a real mesh, whole and on a canvas: h1..h3 and r on every vertex, summing to g;
// off the canvas the modes are zero. The same input gives the same bits.
TEST(EmdNode, DecomposesTheSignalOfARealMeshWholeAndOnACanvas) {
  const MeshPtr bunny = readMesh(test::meshPath("bunny_small.obj")).mesh;
  const auto signal = signalOf(bunny);
  ASSERT_TRUE(signal);
  const auto canvas = std::make_shared<const Canvas>(test::growDiscCanvas(bunny, 100, 2.0));
  auto onCanvas = std::make_shared<Parameterization>();
  onCanvas->canvas = canvas;
  for (const bool partial : {false, true}) {
    std::map<std::string, ValuePtr, std::less<>> inputs{{"mesh", bunny}, {"signal", signal}};
    if (partial) inputs["parameterization"] = onCanvas;
    std::shared_ptr<const VertexFields> first;
    for (int run = 0; run < 2; ++run) {
      test::DirectContext ctx(nodeType("geobrush.emd"), inputs);
      nodeType("geobrush.emd").create()->compute(ctx);
      const auto modes = std::dynamic_pointer_cast<const VertexFields>(ctx.outputs["modes"]);
      const auto report = std::dynamic_pointer_cast<const Metrics>(ctx.outputs["report"]);
      ASSERT_TRUE(modes && report);
      EXPECT_EQ(modes->names(), (std::vector<std::string>{"h1", "h2", "h3", "r"}));
      EXPECT_EQ(modes->mismatch(bunny->surface), "");
      EXPECT_EQ(report->values.at("modes_found"), 3);
      EmdResult asResult{{modes->column("h1"), modes->column("h2"), modes->column("h3")},
                         modes->column("r"),
                         {},
                         3};
      expectSumsBack(asResult, signal->column("g"));
      if (partial) {
        std::vector<std::uint8_t> inside(bunny->surface.n_vertices(), 0);
        for (int v : canvas->sourceVertex)
          inside[std::size_t(v)] = 1;
        for (std::size_t i = 0; i < inside.size(); ++i)
          if (!inside[i]) {
            EXPECT_EQ(modes->column("h1")[i], 0.0);
          }
      }
      if (first) {
        EXPECT_EQ(first->contentHash(), modes->contentHash());
      }
      first = modes;
    }
  }
}

TEST(EmdNode, RefusesASignalOfAnotherMeshAndAMissingField) {
  const MeshPtr bunny = readMesh(test::meshPath("bunny_small.obj")).mesh;
  const MeshPtr grid = test::heightGrid(4, [](double, double) { return 0.0; });
  const auto signal = signalOf(grid);
  {
    test::DirectContext ctx(nodeType("geobrush.emd"), {{"mesh", bunny}, {"signal", signal}});
    try {
      nodeType("geobrush.emd").create()->compute(ctx);
      FAIL();
    } catch (const NodeError& e) {
      EXPECT_EQ(e.where(), "input 'signal'");
    }
  }
  test::DirectContext ctx(nodeType("geobrush.emd"), {{"mesh", grid}, {"signal", signal}},
                          {{"field", std::string("curvature")}});
  try {
    nodeType("geobrush.emd").create()->compute(ctx);
    FAIL();
  } catch (const NodeError& e) {
    EXPECT_EQ(e.where(), "param 'field'");
    EXPECT_TRUE(test::contains(e.what(), "no field 'curvature'"));
  }
}

}  // namespace
}  // namespace geobrush
