#version 450
// The texture copy's rasterization ("Mesh Geometric Editing Approach Based on GPU Texture": the
// CPU builds the face-id list, the GPU fills the texture), one invocation per texel, one workgroup
// per tile: the first face of the tile's list (ordered by depth on the CPU) whose snapped uv
// triangle holds the texel's centre wins it. Integer arithmetic only, with 64-bit products as
// (high, low) pairs (no int64 device feature needed), so nodes/texture_roi/texture_roi.cpp's CPU
// twin computes the same bits.
layout(local_size_x = 8, local_size_y = 8) in;  // kTextureTile

// Per ordered face: x0, y0, x1, y1, x2, y2 (fixed point, counter-clockwise), face id, padding.
layout(std430, set = 0, binding = 0) readonly buffer Faces {
  int faces[];
};
layout(std430, set = 0, binding = 1) readonly buffer TileStart {
  int tileStart[];
};
layout(std430, set = 0, binding = 2) readonly buffer TileFaces {
  int tileFaces[];
};
// Per texel: face id + 1, then the edge weights of corners 1 and 2 as (low, high) words.
layout(std430, set = 0, binding = 3) writeonly buffer Texels {
  uint texels[];
};

layout(push_constant) uniform Raster {
  int size;
  int tilesPerSide;
  int subtexelBits;
}
raster;

struct Wide {
  int hi;
  uint lo;
};

// d x r = d.x r.y - d.y r.x, exactly.
Wide cross2(ivec2 d, ivec2 r) {
  int aHi, aLo, bHi, bLo;
  imulExtended(d.x, r.y, aHi, aLo);
  imulExtended(d.y, r.x, bHi, bLo);
  uint borrow;
  const uint lo = usubBorrow(uint(aLo), uint(bLo), borrow);
  return Wide(aHi - bHi - int(borrow), lo);
}

// The fill rule that gives a texel centre on an edge shared by two faces to exactly one of them:
// the edge a -> b owns it when it points down, or right when horizontal.
bool owns(ivec2 d) {
  return d.y < 0 || (d.y == 0 && d.x > 0);
}

bool holds(Wide e, ivec2 d) {
  const bool zero = e.hi == 0 && e.lo == 0u;
  return e.hi > 0 || (e.hi == 0 && !zero) || (zero && owns(d));
}

void main() {
  const ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
  if (texel.x >= raster.size || texel.y >= raster.size) return;
  const int halfTexel = 1 << (raster.subtexelBits - 1);
  const ivec2 p = texel * (2 * halfTexel) + ivec2(halfTexel);
  const int tile = int(gl_WorkGroupID.y) * raster.tilesPerSide + int(gl_WorkGroupID.x);
  const uint out0 = uint(texel.y * raster.size + texel.x) * 5u;
  texels[out0] = 0u;
  texels[out0 + 1u] = 0u;
  texels[out0 + 2u] = 0u;
  texels[out0 + 3u] = 0u;
  texels[out0 + 4u] = 0u;
  for (int k = tileStart[tile]; k < tileStart[tile + 1]; ++k) {
    const int f = tileFaces[k] * 8;
    const ivec2 p0 = ivec2(faces[f], faces[f + 1]);
    const ivec2 p1 = ivec2(faces[f + 2], faces[f + 3]);
    const ivec2 p2 = ivec2(faces[f + 4], faces[f + 5]);
    const Wide e0 = cross2(p2 - p1, p - p1);
    const Wide e1 = cross2(p0 - p2, p - p2);
    const Wide e2 = cross2(p1 - p0, p - p0);
    if (holds(e0, p2 - p1) && holds(e1, p0 - p2) && holds(e2, p1 - p0)) {
      texels[out0] = uint(faces[f + 6] + 1);
      texels[out0 + 1u] = e1.lo;
      texels[out0 + 2u] = uint(e1.hi);
      texels[out0 + 3u] = e2.lo;
      texels[out0 + 4u] = uint(e2.hi);
      return;
    }
  }
}
