// The inner loop of the Green-coordinates precompute in plain arrays, so that its AVX2 + FMA
// version (nodes/gc_warp/green_kernel_avx2.cpp) shares no templates with the rest of the program.
#pragma once

namespace geobrush::green_kernel {

// Per face, kFaceStride doubles: the unit normal n (3), the in-plane outward edge normals
// m_0, m_1, m_2 (9), the hat weights |grad Gamma_l| / (4 pi) (3), the Gram matrix m_k . m_e
// row by row (9) and twice the area (1).
constexpr int kFaceStride = 25;
constexpr int kNormal = 0, kEdgeNormal = 3, kHatWeight = 12, kGram = 15, kTwiceArea = 24;

// The source cage, read-only. Edge e runs from edgeEnd[2e] to edgeEnd[2e + 1] with unit
// direction edgeDir[3e..]; face f has corners faceVertex[3f..] and edges faceEdge[3f..], edge k
// of a face running from its corner k to corner k + 1.
struct Cage {
  int vertexCount = 0;
  int edgeCount = 0;
  int faceCount = 0;
  const double* vertex = nullptr;  // 3 per vertex
  const int* edgeEnd = nullptr;
  const double* edgeDir = nullptr;
  const double* edgeLength = nullptr;
  const int* faceVertex = nullptr;
  const int* faceEdge = nullptr;
  const double* face = nullptr;
  double tolerance = 0;  // distance below which a point counts as in a face's plane
};

// Doubles of 32-byte aligned scratch memory fourPoints needs.
inline long fourPointsScratchSize(const Cage& cage) {
  return 4L * (5L * cage.vertexCount + cage.edgeCount);
}

// The phi and psi rows of four points at once, one point per vector lane, where
// simd::hasAvx2Fma(). Returns false, with
// the rows unspecified, when a point lies within the tolerance of a face's plane: those points
// need the scalar path, which gives points on the cage their interior limits. `inside` tells
// whether each point's total solid angle is 4 pi.
bool fourPoints(const Cage& cage, const double* const points[4], double* const phiRow[4],
                double* const psiRow[4], bool inside[4], double* scratch);

}  // namespace geobrush::green_kernel
