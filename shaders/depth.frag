#version 450
// Ground-truth pass (one sample, never anti-aliased): depth along the optical
// axis in metres and the object id (1 receiver, 2 tanker, 3 board; the
// background, 4 and 5, comes from background.frag).

layout(location = 0) in vec3 in_normal_in_tanker;
layout(location = 1) in vec2 in_uv;
layout(location = 2) in float in_depth_m;

layout(push_constant) uniform PushConstants {
  mat4 clip_from_object;
  vec4 tanker_from_object_rows[3];
  vec4 base_color_factor;  // .a carries the object id in this pass
} pc;

layout(location = 0) out vec2 out_depth_and_id;

void main() {
  out_depth_and_id = vec2(in_depth_m, pc.base_color_factor.a);
}
