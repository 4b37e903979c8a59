// Four points per AVX2 vector: the same per-face terms as addFace in gc_warp.cpp (LLCO08
// section 3), with the edge log integrals and solid angles of four points computed together.
// This file is compiled with -mavx2 -mfma (geobrush/simd.hpp says why) and runs only where
// simd::hasAvx2Fma() says so.
#include "green_kernel.hpp"

#if defined(__x86_64__) && defined(__AVX2__) && defined(__FMA__)

#include <immintrin.h>

// glibc's vector math library (libmvec), x86-64 vector function ABI, AVX2 variants: log and
// atan2 of four doubles, within 4 ulp.
extern "C" __m256d _ZGVdN4v_log(__m256d x);
extern "C" __m256d _ZGVdN4vv_atan2(__m256d y, __m256d x);

namespace geobrush::green_kernel {
namespace {

using v4d = double __attribute__((vector_size(32)));
using v4l = long long __attribute__((vector_size(32)));

constexpr double kInvFourPi = 0.07957747154594767;  // 1 / (4 pi)
constexpr double kFourPi = 12.566370614359172;
constexpr double kMaxLogRatio = 1e300;

inline v4d splat(double x) {
  return v4d{x, x, x, x};
}
inline v4d sqrt4(v4d x) {
  return _mm256_sqrt_pd(x);
}
inline v4d abs4(v4d x) {
  return _mm256_andnot_pd(splat(-0.0), x);
}
inline v4d select(v4l mask, v4d yes, v4d no) {
  return _mm256_blendv_pd(no, yes, __m256d(mask));
}
inline bool any(v4l mask) {
  return _mm256_movemask_pd(__m256d(mask)) != 0;
}

// The per-point data of one cage vertex: its offset from the four points and its distance.
struct VertexLanes {
  v4d x, y, z, r;
};

// edgeLogIntegral of gc_warp.cpp for four points: the integral of 1/r over the edge, each
// branch free of the cancellation of R + s with s < 0.
inline v4d edgeLog(v4d sa, double length, v4d ra, v4d rb, v4d r0sq) {
  const v4d sb = sa + length;
  const v4l before = sa >= 0, after = sb <= 0;
  v4d num = select(before, rb + sb, select(after, ra - sa, (rb + sb) * (ra - sa)));
  v4d den = select(before, ra + sa, select(after, rb - sb, r0sq));
  const v4l finite = den * kMaxLogRatio > num;
  // Lanes whose ratio is replaced by 0 below get a harmless argument.
  const v4d ratio = select(finite, num / select(finite, den, splat(1.0)), splat(1.0));
  return select(finite, v4d(_ZGVdN4v_log(ratio)), splat(0.0));
}

}  // namespace

bool fourPoints(const Cage& cage, const double* const points[4], double* const phiRow[4],
                double* const psiRow[4], bool inside[4], double* scratch) {
  const int nv = cage.vertexCount, ne = cage.edgeCount, nf = cage.faceCount;
  auto* vertexLanes = reinterpret_cast<VertexLanes*>(scratch);
  auto* logIntegral = reinterpret_cast<v4d*>(scratch + 16L * nv);
  auto* phi = reinterpret_cast<v4d*>(scratch + 16L * nv + 4L * ne);

  const v4d ex = {points[0][0], points[1][0], points[2][0], points[3][0]};
  const v4d ey = {points[0][1], points[1][1], points[2][1], points[3][1]};
  const v4d ez = {points[0][2], points[1][2], points[2][2], points[3][2]};
  for (int v = 0; v < nv; ++v) {
    const double* p = cage.vertex + 3 * v;
    VertexLanes& lane = vertexLanes[v];
    lane.x = p[0] - ex;
    lane.y = p[1] - ey;
    lane.z = p[2] - ez;
    lane.r = sqrt4(lane.x * lane.x + lane.y * lane.y + lane.z * lane.z);
    phi[v] = splat(0.0);
  }
  for (int e = 0; e < ne; ++e) {
    const VertexLanes& a = vertexLanes[cage.edgeEnd[2 * e]];
    const VertexLanes& b = vertexLanes[cage.edgeEnd[2 * e + 1]];
    const double* t = cage.edgeDir + 3 * e;
    const v4d sa = t[0] * a.x + t[1] * a.y + t[2] * a.z;
    const v4d cx = t[1] * a.z - t[2] * a.y;
    const v4d cy = t[2] * a.x - t[0] * a.z;
    const v4d cz = t[0] * a.y - t[1] * a.x;
    logIntegral[e] = edgeLog(sa, cage.edgeLength[e], a.r, b.r, cx * cx + cy * cy + cz * cz);
  }

  v4d solidAngle = splat(0.0);
  v4l nearPlane = {0, 0, 0, 0};
  for (int f = 0; f < nf; ++f) {
    const double* g = cage.face + long(kFaceStride) * f;
    const int* corner = cage.faceVertex + 3 * f;
    const int* edge = cage.faceEdge + 3 * f;
    const VertexLanes& v0 = vertexLanes[corner[0]];
    const VertexLanes& v1 = vertexLanes[corner[1]];
    const VertexLanes& v2 = vertexLanes[corner[2]];
    const double* n = g + kNormal;
    const double* m = g + kEdgeNormal;
    const v4d d = n[0] * v0.x + n[1] * v0.y + n[2] * v0.z;
    const v4d h0 = m[0] * v0.x + m[1] * v0.y + m[2] * v0.z;
    const v4d h1 = m[3] * v1.x + m[4] * v1.y + m[5] * v1.z;
    const v4d h2 = m[6] * v2.x + m[7] * v2.y + m[8] * v2.z;
    const v4d l0 = logIntegral[edge[0]], l1 = logIntegral[edge[1]], l2 = logIntegral[edge[2]];
    const double* w = g + kHatWeight;
    const double* gram = g + kGram;
    const v4d gramL0 = gram[0] * l0 + gram[1] * l1 + gram[2] * l2;
    const v4d gramL1 = gram[3] * l0 + gram[4] * l1 + gram[5] * l2;
    const v4d gramL2 = gram[6] * l0 + gram[7] * l1 + gram[8] * l2;
    nearPlane |= abs4(d) <= cage.tolerance;

    const v4d dot01 = v0.x * v1.x + v0.y * v1.y + v0.z * v1.z;
    const v4d dot02 = v0.x * v2.x + v0.y * v2.y + v0.z * v2.z;
    const v4d dot12 = v1.x * v2.x + v1.y * v2.y + v1.z * v2.z;
    const v4d den = v0.r * v1.r * v2.r + dot01 * v2.r + dot02 * v1.r + dot12 * v0.r;
    const v4d omega = 2.0 * v4d(_ZGVdN4vv_atan2(g[kTwiceArea] * d, den));
    solidAngle += omega;

    phi[corner[0]] += d * w[0] * gramL1 + h1 * w[0] * omega;
    phi[corner[1]] += d * w[1] * gramL2 + h2 * w[1] * omega;
    phi[corner[2]] += d * w[2] * gramL0 + h0 * w[2] * omega;
    const v4d psi = (h0 * l0 + h1 * l1 + h2 * l2 - d * omega) * kInvFourPi;
    for (int lane = 0; lane < 4; ++lane)
      psiRow[lane][f] = psi[lane];
  }
  if (any(nearPlane)) return false;

  const v4l in = abs4(solidAngle - kFourPi) < 0.5 * kFourPi;
  for (int lane = 0; lane < 4; ++lane) {
    inside[lane] = in[lane] != 0;
    for (int v = 0; v < nv; ++v)
      phiRow[lane][v] = phi[v][lane];
  }
  return true;
}

}  // namespace geobrush::green_kernel

#else

namespace geobrush::green_kernel {

bool fourPoints(const Cage&, const double* const*, double* const*, double* const*, bool*, double*) {
  return false;
}

}  // namespace geobrush::green_kernel

#endif
