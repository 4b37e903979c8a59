#version 450
// One pass of the operator of a level of the offset membrane's multigrid (GeoBrush paper section
// 4.4, Eq. 4), one invocation per node of the level's padded grid: A x, b - A x, or a step of the
// Chebyshev smoother. nodes/membrane/membrane_levels.cpp computes the same on the CPU.
layout(local_size_x = 64) in;

// Every vector of the level in one buffer, and every coefficient in another, at offsets the push
// constants give: one descriptor set serves every pass, ping-pong included.
layout(std430, set = 0, binding = 0) buffer Vectors {
  float vectors[];
};
layout(std430, set = 0, binding = 1) readonly buffer Coefficients {
  float coefficients[];
};
// Per node: the index of its custom row, or -1 for the regular stencil.
layout(std430, set = 0, binding = 2) readonly buffer CustomOf {
  int customOf[];
};

const int kApply = 0;      // out = mask (A x)
const int kSubtract = 1;   // out = mask (b - A x)
const int kChebyshev = 2;  // d = keep d + gain D^-1 (b - A x), out = x + d
const int kReach = 3;      // stencils are 7 x 7, row-major
const int kSlots = 49;

// The level's regular stencil: the finest level's written out, else its 49 weights.
const int kFull = 0;
const int kPlate = 1;    // the 13-point biharmonic
const int kLaplace = 2;  // the 5-point Laplacian

layout(push_constant) uniform Pass {
  int begin;  // first padded index of the pass
  int count;  // nodes in the pass
  int stride;
  int mode;
  int shape;
  int b;  // offsets into `vectors`
  int x;
  int d;
  int outValues;
  int mask;  // offsets into `coefficients`
  int inverseDiagonal;
  int regular;
  int custom;
  float keep;
  float gain;
}
pass;

float value(int node, int dx, int dy) {
  return vectors[pass.x + node + dy * pass.stride + dx];
}

float stencilSum(int node) {
  const int row = customOf[node];
  if (row < 0 && pass.shape == kPlate)
    return 20.0 * value(node, 0, 0) -
           8.0 * (value(node, -1, 0) + value(node, 1, 0) + value(node, 0, -1) + value(node, 0, 1)) +
           2.0 * (value(node, -1, -1) + value(node, 1, -1) + value(node, -1, 1) +
                  value(node, 1, 1)) +
           (value(node, -2, 0) + value(node, 2, 0) + value(node, 0, -2) + value(node, 0, 2));
  if (row < 0 && pass.shape == kLaplace)
    return 4.0 * value(node, 0, 0) -
           (value(node, -1, 0) + value(node, 1, 0) + value(node, 0, -1) + value(node, 0, 1));
  const int weights = row < 0 ? pass.regular : pass.custom + kSlots * row;
  float sum = 0.0;
  for (int dy = -kReach; dy <= kReach; ++dy) {
    const int slots = weights + (dy + kReach) * (2 * kReach + 1) + kReach;
    for (int dx = -kReach; dx <= kReach; ++dx)
      sum += coefficients[slots + dx] * value(node, dx, dy);
  }
  return sum;
}

void main() {
  const int i = int(gl_GlobalInvocationID.x);
  if (i >= pass.count) return;
  const int node = pass.begin + i;
  const float sum = stencilSum(node);
  const float m = coefficients[pass.mask + node];
  if (pass.mode == kApply) {
    vectors[pass.outValues + node] = m * sum;
  } else if (pass.mode == kSubtract) {
    vectors[pass.outValues + node] = m * (vectors[pass.b + node] - sum);
  } else {
    const float residual = vectors[pass.b + node] - sum;
    // inverseDiagonal is 0 off the unknowns, which keeps d and out at 0 there.
    const float step = pass.keep * vectors[pass.d + node] +
                       pass.gain * coefficients[pass.inverseDiagonal + node] * residual;
    vectors[pass.d + node] = step;
    vectors[pass.outValues + node] = vectors[pass.x + node] + step;
  }
}
