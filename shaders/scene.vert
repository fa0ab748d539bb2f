#version 450
// Transforms body-frame vertices of one object to clip space. The projection
// maps the OpenCV camera frame (x right, y down, z forward) to Vulkan clip
// space with reversed infinite depth, so gl_Position.w is the depth along the
// optical axis in metres.

layout(location = 0) in vec3 in_position;  // object (body) frame [m]
layout(location = 1) in vec3 in_normal;    // object (body) frame
layout(location = 2) in vec2 in_uv;

layout(push_constant) uniform PushConstants {
  mat4 clip_from_object;
  vec4 tanker_from_object_rows[3];  // rotation rows (xyz) of tanker_from_object; w: the material (scene.frag)
  vec4 base_color_factor;           // linear RGBA
} pc;

layout(location = 0) out vec3 out_normal_in_tanker;
layout(location = 1) out vec2 out_uv;
layout(location = 2) out float out_depth_m;
layout(location = 3) out vec3 out_to_camera_in_tanker;  // from the surface to the camera's centre [m]
layout(location = 4) out vec3 out_position_in_tanker;   // [m]

void main() {
  // Row 2 of clip_from_object is (0, 0, 0, near) for every camera
  // (projection.h): z_clip is near, and the row's first three entries carry
  // tanker_from_object's translation instead (scene_renderer.cpp).
  gl_Position = pc.clip_from_object * vec4(in_position, 1.0);
  gl_Position.z = pc.clip_from_object[3][2];
  mat3 tanker_from_object_t = mat3(pc.tanker_from_object_rows[0].xyz,
                                   pc.tanker_from_object_rows[1].xyz,
                                   pc.tanker_from_object_rows[2].xyz);
  // mat3(rows) builds the transpose; multiply on the left to apply the rows.
  out_normal_in_tanker = in_normal * tanker_from_object_t;
  out_uv = in_uv;
  out_depth_m = gl_Position.w;
  // The camera's centre c (object frame) is where clip x, y and w all vanish:
  // rows 0, 1 and 3 of clip_from_object give A c = -b (mat3 takes columns).
  const mat4 p = pc.clip_from_object;
  mat3 a = mat3(vec3(p[0][0], p[0][1], p[0][3]), vec3(p[1][0], p[1][1], p[1][3]), vec3(p[2][0], p[2][1], p[2][3]));
  vec3 centre = inverse(a) * -vec3(p[3][0], p[3][1], p[3][3]);
  out_to_camera_in_tanker = (centre - in_position) * tanker_from_object_t;
  out_position_in_tanker = in_position * tanker_from_object_t +
                           vec3(pc.clip_from_object[0][2], pc.clip_from_object[1][2], pc.clip_from_object[2][2]);
}
