// Mesh renderer, vertex stage: see core/src/render_scene.hpp for the inputs.
#version 450

layout(push_constant) uniform Shading {
  mat4 viewProjection;
  vec4 headlight;
  vec4 fillLight;
  vec4 material;
} shading;

layout(location = 0) in vec3 inPosition;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec3 inColor;
layout(location = 3) in vec3 inEdgeLine0;
layout(location = 4) in vec3 inEdgeLine1;
layout(location = 5) in vec3 inEdgeLine2;
layout(location = 6) in float inWireframe;

layout(location = 0) out vec3 vNormal;
layout(location = 1) out vec3 vColor;
layout(location = 2) flat out vec3 vEdgeLine0;
layout(location = 3) flat out vec3 vEdgeLine1;
layout(location = 4) flat out vec3 vEdgeLine2;
layout(location = 5) flat out float vWireframe;

void main() {
  gl_Position = shading.viewProjection * vec4(inPosition, 1.0);
  vNormal = inNormal;
  vColor = inColor;
  vEdgeLine0 = inEdgeLine0;
  vEdgeLine1 = inEdgeLine1;
  vEdgeLine2 = inEdgeLine2;
  vWireframe = inWireframe;
}
