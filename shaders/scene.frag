#version 450
// Lambertian shading under a fixed sun, in linear colour. The render target is
// a floating-point image; sRGB encoding happens after MSAA composition.
// Compiled a second time with AAR_PBR (scene_pbr_frag, --shading pbr): glTF
// metallic-roughness shading, the same diffuse light plus the sun's and the
// sky's specular reflection (docs/rendering.md, "Physically based shading").
// With AAR_SHADOWS (scene_shadow_frag, scene_pbr_shadow_frag; --shadows) the
// sun's light, diffuse and specular, is scaled by its visibility in the sun
// camera's depth map (shadow_map.h; docs/rendering.md, "Shadows").

layout(location = 0) in vec3 in_normal_in_tanker;
layout(location = 1) in vec2 in_uv;
layout(location = 2) in float in_depth_m;
#if defined(AAR_PBR) || defined(AAR_SHADOWS)
layout(location = 3) in vec3 in_to_camera_in_tanker;
#endif
layout(location = 4) in vec3 in_position_in_tanker;

layout(push_constant) uniform PushConstants {
  mat4 clip_from_object;
  vec4 tanker_from_object_rows[3];  // w of rows 0 and 1: metallic and roughness (AAR_PBR); of row 2: 1 for a light
  vec4 base_color_factor;
} pc;

layout(set = 0, binding = 0) uniform sampler2D base_color_texture;

layout(location = 0) out vec4 out_color;

#ifdef AAR_SHADOWS
// The sun camera's depth along its axis [m] per texel, 0 where no surface
// (shadow_map.h), and where it is; ShadowUniforms there, member for member.
layout(set = 1, binding = 0) uniform sampler2D sun_depth_map;
layout(set = 1, binding = 1) uniform ShadowUniforms {
  mat4 sun_camera_from_tanker;
  vec4 sun_intrinsics;             // fx, fy, cx, cy [px]
  vec4 camera_centre_in_tanker;    // xyz: the viewing camera's centre [m]
  vec4 map;                        // width, height [texels], depth bias: constant [m], per unit slope [texels]
} shadow;

// The share of the four texels around the point's projection (bilinear
// weights, texel i's centre at pixel coordinate i) whose surface is not
// nearer the sun than the point, less a bias for the map's sampling: the
// sun's visibility, 0 in shadow, 1 in the sun, between at a shadow's edge.
float SunVisibility(vec3 p_in_tanker, float n_dot_sun) {
  vec3 q = (shadow.sun_camera_from_tanker * vec4(p_in_tanker, 1.0)).xyz;
  if (q.z <= 0.0) return 1.0;
  vec2 uv = shadow.sun_intrinsics.xy * q.xy / q.z + shadow.sun_intrinsics.zw;
  vec2 base = floor(uv);
  vec2 f = uv - base;
  // A texel's depth was sampled up to 1.5 texels away on a surface whose
  // depth changes by tan(angle to the sun) per texel's width.
  float texel_m = q.z / shadow.sun_intrinsics.x;
  float c = clamp(n_dot_sun, 0.05, 1.0);
  float bias = shadow.map.z + shadow.map.w * texel_m * sqrt(1.0 - c * c) / c;
  float visible = 0.0;
  for (int j = 0; j < 2; ++j) {
    for (int i = 0; i < 2; ++i) {
      ivec2 t = ivec2(base) + ivec2(i, j);
      float lit = 1.0;
      if (t.x >= 0 && t.y >= 0 && t.x < int(shadow.map.x) && t.y < int(shadow.map.y)) {
        float d = texelFetch(sun_depth_map, t, 0).r;
        if (d > 0.0 && d < q.z - bias) lit = 0.0;
      }
      visible += lit * (i == 0 ? 1.0 - f.x : f.x) * (j == 0 ? 1.0 - f.y : f.y);
    }
  }
  return visible;
}
#endif

// The sun (unit vector, tanker frame), set per pipeline from
// background.h's SunInLevel() and the tanker's attitude; the defaults are
// the level tanker's: above, ahead and to the left. Plus sky light.
layout(constant_id = 0) const float kSunX = 0.35045588;
layout(constant_id = 1) const float kSunY = 0.45058614;
layout(constant_id = 2) const float kSunZ = 0.82106811;
const vec3 kSunDirection = vec3(kSunX, kSunY, kSunZ);
const float kSunIntensity = 0.75;
const float kAmbient = 0.35;
// With kDaylight (--daylight; daylight.h, docs/rendering.md "Daylight"): the
// sun's light at the tanker per channel, and the sky's radiance as A + B w.z
// (A, B from the irradiance / pi on faces looking up and down); else the
// fixed light above.
layout(constant_id = 3) const int kDaylight = 0;
layout(constant_id = 4) const float kSunLightR = 0.75;
layout(constant_id = 5) const float kSunLightG = 0.75;
layout(constant_id = 6) const float kSunLightB = 0.75;
layout(constant_id = 7) const float kDaySkyAR = 0.0;
layout(constant_id = 8) const float kDaySkyAG = 0.0;
layout(constant_id = 9) const float kDaySkyAB = 0.0;
layout(constant_id = 10) const float kDaySkyBR = 0.0;
layout(constant_id = 11) const float kDaySkyBG = 0.0;
layout(constant_id = 12) const float kDaySkyBB = 0.0;
const vec3 kSunLight = vec3(kSunLightR, kSunLightG, kSunLightB);
const vec3 kDaySkyA = vec3(kDaySkyAR, kDaySkyAG, kDaySkyAB);
const vec3 kDaySkyB = vec3(kDaySkyBR, kDaySkyBG, kDaySkyBB);
// With kFloodlight (--floodlight; floodlight.h, docs/rendering.md "Night"):
// a white point light at kFlood (tanker frame) aimed along kFloodAxis, its
// intensity a Gaussian of the angle off the axis (sigma kFloodSigma rad),
// kFloodIntensity on the axis in the units of kSunLight at 1 m.
layout(constant_id = 13) const int kFloodlight = 0;
layout(constant_id = 14) const float kFloodX = 0.0;
layout(constant_id = 15) const float kFloodY = 0.0;
layout(constant_id = 16) const float kFloodZ = 0.0;
layout(constant_id = 17) const float kFloodAxisX = -1.0;
layout(constant_id = 18) const float kFloodAxisY = 0.0;
layout(constant_id = 19) const float kFloodAxisZ = 0.0;
layout(constant_id = 20) const float kFloodIntensity = 0.0;
layout(constant_id = 21) const float kFloodSigma = 0.1745;
const vec3 kFlood = vec3(kFloodX, kFloodY, kFloodZ);
const vec3 kFloodAxis = vec3(kFloodAxisX, kFloodAxisY, kFloodAxisZ);

// The floodlight's direction from the surface (xyz) and its light there (w):
// what a surface facing it receives, in the units of kSunLight.
vec4 Floodlight() {
  vec3 d = kFlood - in_position_in_tanker;
  float d2 = dot(d, d);
  vec3 l = d * inversesqrt(d2);
  float off_axis = acos(clamp(dot(-l, kFloodAxis), -1.0, 1.0));
  return vec4(l, kFloodIntensity * exp(-0.5 * off_axis * off_axis / (kFloodSigma * kFloodSigma)) / d2);
}

#ifdef AAR_PBR
const float kPi = 3.14159265358979;
// The sky's radiance in direction w, in the units of the diffuse term: the
// matte model's sky light kAmbient (0.75 + 0.25 n.z) is the irradiance / pi
// of a sky whose radiance is linear in w.z, L(w) = A + B w.z, since a
// Lambertian surface then returns A + (2/3) B n.z.
const float kSkyA = kAmbient * 0.75;
const float kSkyB = kAmbient * 0.25 * 1.5;
vec3 SkyRadiance(vec3 w) {
  return kDaylight != 0 ? kDaySkyA + kDaySkyB * clamp(w.z, -1.0, 1.0) : vec3(kSkyA + kSkyB * clamp(w.z, -1.0, 1.0));
}

// GGX (Trowbridge-Reitz) distribution, alpha = roughness^2 (glTF 2.0
// specification, appendix B).
float DistributionGgx(float n_dot_h, float alpha) {
  float a2 = alpha * alpha;
  float d = n_dot_h * n_dot_h * (a2 - 1.0) + 1.0;
  return a2 / (kPi * d * d);
}
// Height-correlated Smith visibility, G / (4 n.l n.v) (glTF 2.0, appendix B).
float VisibilitySmithGgx(float n_dot_l, float n_dot_v, float alpha) {
  float a2 = alpha * alpha;
  float gv = n_dot_l * sqrt(n_dot_v * n_dot_v * (1.0 - a2) + a2);
  float gl = n_dot_v * sqrt(n_dot_l * n_dot_l * (1.0 - a2) + a2);
  float g = gv + gl;
  return g > 0.0 ? 0.5 / g : 0.0;
}
vec3 FresnelSchlick(vec3 f0, vec3 f90, float cos_theta) {
  return f0 + (f90 - f0) * pow(clamp(1.0 - cos_theta, 0.0, 1.0), 5.0);
}
#endif

void main() {
  // A light (receiver_lights.h): its radiance, unlit, kept below half
  // floats' largest value (65504) so that averaging stays finite.
  if (pc.tanker_from_object_rows[2].w > 0.5) {
    out_color = vec4(min(pc.base_color_factor.rgb, vec3(60000.0)), 1.0);
    return;
  }
  vec3 n = normalize(in_normal_in_tanker);
  if (!gl_FrontFacing) n = -n;
  // Sky light is brighter from above: a hemisphere term keeps bellies textured.
  vec3 sky = kDaylight != 0 ? kDaySkyA + (2.0 / 3.0) * kDaySkyB * n.z : vec3(kAmbient * (0.75 + 0.25 * n.z));
  vec3 sun_light = kDaylight != 0 ? kSunLight : vec3(kSunIntensity);
#ifdef AAR_SHADOWS
  float sun = SunVisibility(shadow.camera_centre_in_tanker.xyz - in_to_camera_in_tanker, dot(n, kSunDirection));
#else
  const float sun = 1.0;
#endif
  vec3 light = sky + sun * sun_light * max(dot(n, kSunDirection), 0.0);
  vec4 flood = vec4(0.0);
  if (kFloodlight != 0) {
    flood = Floodlight();
    light += vec3(flood.w * max(dot(n, flood.xyz), 0.0));
  }
  vec4 albedo = pc.base_color_factor * texture(base_color_texture, in_uv);
#ifdef AAR_PBR
  float metallic = pc.tanker_from_object_rows[0].w;
  float roughness = clamp(pc.tanker_from_object_rows[1].w, 0.03, 1.0);  // a point sun needs a finite lobe
  float alpha = roughness * roughness;
  vec3 v = normalize(in_to_camera_in_tanker);
  float n_dot_v = max(dot(n, v), 1e-4);
  vec3 f0 = mix(vec3(0.04), albedo.rgb, metallic);  // 4 %: a dielectric of refractive index 1.5
  // The sun, a point source whose irradiance is kSunIntensity pi (the
  // Lambertian term above is albedo / pi times it).
  float n_dot_l = max(dot(n, kSunDirection), 0.0);
  vec3 h = normalize(kSunDirection + v);
  vec3 f_sun = FresnelSchlick(f0, vec3(1.0), max(dot(v, h), 0.0));
  vec3 sun_specular = f_sun * DistributionGgx(max(dot(n, h), 0.0), alpha) *
                      VisibilitySmithGgx(n_dot_l, n_dot_v, alpha) * (sun * sun_light * kPi) * n_dot_l;
  if (kFloodlight != 0) {
    // The floodlight's reflection, a point source like the sun.
    float f_n_dot_l = max(dot(n, flood.xyz), 0.0);
    vec3 f_h = normalize(flood.xyz + v);
    sun_specular += FresnelSchlick(f0, vec3(1.0), max(dot(v, f_h), 0.0)) *
                    DistributionGgx(max(dot(n, f_h), 0.0), alpha) * VisibilitySmithGgx(f_n_dot_l, n_dot_v, alpha) *
                    (flood.w * kPi) * f_n_dot_l;
  }
  // The sky, mirrored about the normal; a rough surface's lobe reaches less
  // of the grazing Fresnel rise (Fdez-Aguera's roughness-dependent f90).
  vec3 f_sky = FresnelSchlick(f0, max(vec3(1.0 - roughness), f0), n_dot_v);
  vec3 sky_specular = f_sky * SkyRadiance(reflect(-v, n));
  vec3 diffuse = (vec3(1.0) - f_sky) * (1.0 - metallic) * albedo.rgb * light;
  out_color = vec4(diffuse + sun_specular + sky_specular, 1.0);
#else
  out_color = vec4(albedo.rgb * light, 1.0);
#endif
}
