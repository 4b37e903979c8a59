// Mesh renderer, fragment stage: the shading model of core/src/render.cpp;
// core/src/render_cpu.cpp computes the same, term by term.
#version 450

layout(push_constant) uniform Shading {
  mat4 viewProjection;
  vec4 headlight;
  vec4 fillLight;
  vec4 material;
} shading;

layout(location = 0) in vec3 vNormal;
layout(location = 1) in vec3 vColor;
layout(location = 2) flat in vec3 vEdgeLine0;
layout(location = 3) flat in vec3 vEdgeLine1;
layout(location = 4) flat in vec3 vEdgeLine2;
layout(location = 5) flat in float vWireframe;

layout(location = 0) out vec4 outColor;

void main() {
  // Pixels from the nearest edge line; gl_FragCoord is the pixel centre.
  vec3 pixel = vec3(gl_FragCoord.xy, 1.0);
  float nearestEdge = min(abs(dot(vEdgeLine0, pixel)),
                          min(abs(dot(vEdgeLine1, pixel)), abs(dot(vEdgeLine2, pixel))));
  float edge = vWireframe * (1.0 - clamp(nearestEdge - 0.5, 0.0, 1.0));

  float normalLength = length(vNormal);
  vec3 normal = normalLength > 1e-20 ? vNormal / normalLength : shading.headlight.xyz;
  float light = shading.material.x +
                shading.headlight.w * max(dot(normal, shading.headlight.xyz), 0.0) +
                shading.fillLight.w * max(dot(normal, shading.fillLight.xyz), 0.0);
  vec3 color = mix(vColor * light, vec3(shading.material.y), edge);
  outColor = vec4(clamp(color, 0.0, 1.0), 1.0);
}
