#version 450
// Lambertian shading under a fixed sun, in linear colour. The render target is
// a floating-point image; sRGB encoding happens after MSAA composition.

layout(location = 0) in vec3 in_normal_in_tanker;
layout(location = 1) in vec2 in_uv;
layout(location = 2) in float in_depth_m;

layout(push_constant) uniform PushConstants {
  mat4 clip_from_object;
  vec4 tanker_from_object_rows[3];
  vec4 base_color_factor;
} pc;

layout(set = 0, binding = 0) uniform sampler2D base_color_texture;

layout(location = 0) out vec4 out_color;

// The sun (unit vector, tanker frame), set per pipeline from
// background.h's SunInLevel() and the tanker's attitude; the defaults are
// the level tanker's: above, ahead and to the left. Plus sky light.
layout(constant_id = 0) const float kSunX = 0.35045588;
layout(constant_id = 1) const float kSunY = 0.45058614;
layout(constant_id = 2) const float kSunZ = 0.82106811;
const vec3 kSunDirection = vec3(kSunX, kSunY, kSunZ);
const float kSunIntensity = 0.75;
const float kAmbient = 0.35;

void main() {
  vec3 n = normalize(in_normal_in_tanker);
  if (!gl_FrontFacing) n = -n;
  // Sky light is brighter from above: a hemisphere term keeps bellies textured.
  float sky = kAmbient * (0.75 + 0.25 * n.z);
  float light = sky + kSunIntensity * max(dot(n, kSunDirection), 0.0);
  vec4 albedo = pc.base_color_factor * texture(base_color_texture, in_uv);
  out_color = vec4(albedo.rgb * light, 1.0);
}
