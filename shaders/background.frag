#version 450
// The background behind the aircraft (docs/rendering.md, "Backgrounds"),
// evaluated per pixel at the pixel's centre without the MSAA pass's jitter, so
// every pass, and the single-sample pass outside the aircraft's rectangle,
// gives the same value. The ray of pixel (u, v) meets a sphere (the ground, or
// the cloud deck's top) analytically (background.h: SphereHitParameter);
// surfaces are lit like scene.frag's upward faces and faded by haze whose
// density falls exponentially with height (HazeOpticalDepth). Compiled twice:
// colour, and with AAR_TRUTH the ground-truth pass (depth, object id).
// With kDaylight (--daylight; daylight.h, docs/rendering.md "Daylight") the
// sky is Preetham's for the sun and turbidity, the haze's airlight the
// horizon's radiance in the ray's azimuth, the surface lit by the sun after
// the atmosphere and by that sky, and the sun's disc drawn where it is.

layout(push_constant) uniform BackgroundPush {
  // xyz: rows of level_from_cam * K^-1 (the level-frame ray, with z_cam = 1, of
  // pixel (u, v, 1)); w: the camera's level x, y [m] and height above the ground [m].
  vec4 level_from_pixel_rows[3];
  vec4 sun_in_level;  // xyz: unit vector to the sun; w: sea-level haze extinction [1/m]
  // x: sin^2 of the surface's horizon dip; y: h (2R + h) / (R + h) [m] (h: camera
  // above the surface, R: the surface's radius); z: surface height [m]; w: haze scale height [m]
  vec4 surface;
  // x: 1 / tile size [1/m]; y: a pixel's angular size [rad] (daylight's sun
  // disc; else 0); z: 0 (unused); w: kind (1 sky, 2 terrain, 3 clouds)
  vec4 texture_map;
} bg;

layout(set = 0, binding = 0) uniform sampler2D surface_texture;

#ifdef AAR_TRUTH
layout(location = 0) out vec2 out_depth_and_id;
#else
layout(location = 0) out vec4 out_color;
#endif

const float kSunIntensity = 0.75;  // scene.frag's lighting, for a face looking up
const float kAmbient = 0.35;
const vec3 kZenith = vec3(0.16, 0.30, 0.62);   // linear RGB
const vec3 kHorizon = vec3(0.60, 0.68, 0.80);  // also the colour of the haze (airlight)
const vec3 kPlainGround = vec3(0.16, 0.17, 0.12);

#ifndef AAR_TRUTH
// Daylight's constants (daylight.cpp, DaylightConstants), set per pipeline.
// Per Perez coefficient A..E, its values for luminance Y and chromaticity x, y.
layout(constant_id = 0) const int kDaylight = 0;
layout(constant_id = 1) const float kAY = 0.0;
layout(constant_id = 2) const float kAx = 0.0;
layout(constant_id = 3) const float kAy = 0.0;
layout(constant_id = 4) const float kBY = 0.0;
layout(constant_id = 5) const float kBx = 0.0;
layout(constant_id = 6) const float kBy = 0.0;
layout(constant_id = 7) const float kCY = 0.0;
layout(constant_id = 8) const float kCx = 0.0;
layout(constant_id = 9) const float kCy = 0.0;
layout(constant_id = 10) const float kDY = 0.0;
layout(constant_id = 11) const float kDx = 0.0;
layout(constant_id = 12) const float kDy = 0.0;
layout(constant_id = 13) const float kEY = 0.0;
layout(constant_id = 14) const float kEx = 0.0;
layout(constant_id = 15) const float kEy = 0.0;
// The zenith's Y (the renderer's units), x, y over the Perez function there.
layout(constant_id = 16) const float kZenithY = 0.0;
layout(constant_id = 17) const float kZenithX = 0.0;
layout(constant_id = 18) const float kZenithChromaY = 0.0;
// What lights the surface (albedo x this), and the sun's disc radiance.
layout(constant_id = 19) const float kSurfaceLightR = 0.0;
layout(constant_id = 20) const float kSurfaceLightG = 0.0;
layout(constant_id = 21) const float kSurfaceLightB = 0.0;
layout(constant_id = 22) const float kSunDiscR = 0.0;
layout(constant_id = 23) const float kSunDiscG = 0.0;
layout(constant_id = 24) const float kSunDiscB = 0.0;
layout(constant_id = 25) const float kSunRadius = 0.0;  // [rad]
const vec3 kA = vec3(kAY, kAx, kAy);
const vec3 kB = vec3(kBY, kBx, kBy);
const vec3 kC = vec3(kCY, kCx, kCy);
const vec3 kD = vec3(kDY, kDx, kDy);
const vec3 kE = vec3(kEY, kEx, kEy);
const vec3 kPreethamZenith = vec3(kZenithY, kZenithX, kZenithChromaY);
const vec3 kSurfaceLight = vec3(kSurfaceLightR, kSurfaceLightG, kSurfaceLightB);
const vec3 kSunDisc = vec3(kSunDiscR, kSunDiscG, kSunDiscB);

// Preetham's sky in a unit level-frame direction, linear sRGB (PreethamSky::Radiance).
vec3 DaylightSky(vec3 d, vec3 sun) {
  vec3 w = d;
  if (w.z < 1e-3) {
    // At and below the horizontal: the horizon in this azimuth.
    vec2 horizontal = dot(w.xy, w.xy) > 1e-12 ? normalize(w.xy) : vec2(1.0, 0.0);
    w = vec3(horizontal, 1e-3);
  }
  float gamma = acos(clamp(dot(normalize(w), sun), -1.0, 1.0));
  float cos_gamma = cos(gamma);
  vec3 yxy = kPreethamZenith * (vec3(1.0) + kA * exp(kB / w.z)) * (vec3(1.0) + kC * exp(kD * gamma) + kE * cos_gamma * cos_gamma);
  float luminance = max(yxy.x, 0.0);
  vec3 xyz = vec3(yxy.y / yxy.z * luminance, luminance, (1.0 - yxy.y - yxy.z) / yxy.z * luminance);
  vec3 rgb = vec3(dot(vec3(3.2404542, -1.5371385, -0.4985314), xyz), dot(vec3(-0.9692660, 1.8760108, 0.0415560), xyz),
                  dot(vec3(0.0556434, -0.2040259, 1.0572252), xyz));
  return max(rgb, vec3(0.0));
}
#endif

void main() {
  const vec3 pixel = vec3(gl_FragCoord.xy - 0.5, 1.0);  // OpenCV (u, v) of this pixel's centre
  const vec3 ray = vec3(dot(bg.level_from_pixel_rows[0].xyz, pixel), dot(bg.level_from_pixel_rows[1].xyz, pixel),
                        dot(bg.level_from_pixel_rows[2].xyz, pixel));
  const float ray_length = length(ray);
  const float dz = ray.z / ray_length;
  const float sin2_dip = bg.surface.x;
  const int kind = int(bg.texture_map.w);
  const bool hit = dz < 0.0 && dz * dz >= sin2_dip;
  // Below the horizon: the distance along the ray to the surface (at the
  // horizon for rays that miss, so texture coordinates stay continuous).
  const float dz_hit = min(dz, -sqrt(sin2_dip));
  const float t = bg.surface.y / (-dz_hit + sqrt(max(dz_hit * dz_hit - sin2_dip, 0.0))) / ray_length;  // = z_cam [m]
#ifdef AAR_TRUTH
  out_depth_and_id = hit ? vec2(t, kind == 3 ? 5.0 : 4.0) : vec2(0.0);
#else
  const vec3 direction = ray / ray_length;
  vec3 color;
  if (hit) {
    vec3 albedo = kPlainGround;
    if (kind != 1) {
      const vec2 ground = vec2(bg.level_from_pixel_rows[0].w, bg.level_from_pixel_rows[1].w) + t * ray.xy;
      const vec2 uv = ground * bg.texture_map.x;
      albedo = texture(surface_texture, uv).rgb;
      if (kind == 2) {
        // A broad brightness modulation at another scale and angle breaks up the tile's repeat.
        const vec2 uv_broad = mat2(0.8, 0.6, -0.6, 0.8) * uv * 0.137 + vec2(0.31, 0.77);
        albedo *= 0.8 + 0.4 * clamp(4.0 * textureLod(surface_texture, uv_broad, 6.0).g, 0.0, 1.0);
      }
    }
    const vec3 light = kDaylight != 0 ? kSurfaceLight : vec3(kAmbient + kSunIntensity * max(bg.sun_in_level.z, 0.0));
    const float height = bg.level_from_pixel_rows[2].w;
    const float length_m = t * ray_length;
    const float scale = bg.surface.w;
    const float dh = height - bg.surface.z;
    const float mean_density = dh < 1.0 ? exp(-0.5 * (height + bg.surface.z) / scale)
                                        : scale * (exp(-bg.surface.z / scale) - exp(-height / scale)) / dh;
    const float transmittance = exp(-bg.sun_in_level.w * length_m * mean_density);
    const vec3 airlight = kDaylight != 0 ? DaylightSky(direction, bg.sun_in_level.xyz) : kHorizon;
    color = mix(airlight, albedo * light, transmittance);
  } else if (kDaylight != 0) {
    color = DaylightSky(direction, bg.sun_in_level.xyz);
    // The sun's disc, its edge spread over a pixel's angular size.
    const float gamma = 2.0 * asin(0.5 * length(direction - bg.sun_in_level.xyz));
    color += kSunDisc * clamp((kSunRadius - gamma) / bg.texture_map.y + 0.5, 0.0, 1.0);
  } else {
    const float above = clamp((dz + sqrt(sin2_dip)) / (1.0 + sqrt(sin2_dip)), 0.0, 1.0);
    color = mix(kHorizon, kZenith, sqrt(above));
    color += vec3(0.5, 0.45, 0.35) * pow(max(dot(direction, bg.sun_in_level.xyz), 0.0), 200.0);
  }
  out_color = vec4(color, 1.0);
#endif
}
