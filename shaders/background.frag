#version 450
// The background behind the aircraft (docs/rendering.md, "Backgrounds"),
// evaluated per pixel at the pixel's centre without the MSAA pass's jitter, so
// every pass, and the single-sample pass outside the aircraft's rectangle,
// gives the same value. The ray of pixel (u, v) meets a sphere (the ground, or
// the cloud deck's top) analytically (background.h: SphereHitParameter);
// surfaces are lit like scene.frag's upward faces and faded by haze whose
// density falls exponentially with height (HazeOpticalDepth). Compiled twice:
// colour, and with AAR_TRUTH the ground-truth pass (depth, object id).

layout(push_constant) uniform BackgroundPush {
  // xyz: rows of level_from_cam * K^-1 (the level-frame ray, with z_cam = 1, of
  // pixel (u, v, 1)); w: the camera's level x, y [m] and height above the ground [m].
  vec4 level_from_pixel_rows[3];
  vec4 sun_in_level;  // xyz: unit vector to the sun; w: sea-level haze extinction [1/m]
  // x: sin^2 of the surface's horizon dip; y: h (2R + h) / (R + h) [m] (h: camera
  // above the surface, R: the surface's radius); z: surface height [m]; w: haze scale height [m]
  vec4 surface;
  vec4 texture_map;  // x: 1 / tile size [1/m]; yz: 0 (unused); w: kind (1 sky, 2 terrain, 3 clouds)
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
    const float light = kAmbient + kSunIntensity * max(bg.sun_in_level.z, 0.0);
    const float height = bg.level_from_pixel_rows[2].w;
    const float length_m = t * ray_length;
    const float scale = bg.surface.w;
    const float dh = height - bg.surface.z;
    const float mean_density = dh < 1.0 ? exp(-0.5 * (height + bg.surface.z) / scale)
                                        : scale * (exp(-bg.surface.z / scale) - exp(-height / scale)) / dh;
    const float transmittance = exp(-bg.sun_in_level.w * length_m * mean_density);
    color = mix(kHorizon, albedo * light, transmittance);
  } else {
    const float above = clamp((dz + sqrt(sin2_dip)) / (1.0 + sqrt(sin2_dip)), 0.0, 1.0);
    color = mix(kHorizon, kZenith, sqrt(above));
    color += vec3(0.5, 0.45, 0.35) * pow(max(dot(direction, bg.sun_in_level.xyz), 0.0), 200.0);
  }
  out_color = vec4(color, 1.0);
#endif
}
