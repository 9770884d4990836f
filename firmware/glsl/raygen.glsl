// The ray-generation shader's body (docs/shading.md sections 1 and 2), as
// firmware/whitted.s does it: spp jittered samples per pixel, each traced; the mean goes
// to the framebuffer. A pinhole camera unless the including shader defines
// RPU_THIN_LENS (thin_lens.rgen). Include from a .rgen after its #version and extension.
#ifndef RPU_RAYGEN_GLSL
#define RPU_RAYGEN_GLSL
#include "rpu.glsl"
#include "payload.glsl"

layout(location = 0) rayPayloadEXT RpuRay ray;

void main() {
  const uvec2 pixel = gl_LaunchIDEXT.xy;
  const uint pixel_index = pixel.y * gl_LaunchSizeEXT.x + pixel.x;
  const int spp = int(launch_record.spp);
  int n = 1;  // one sample: no sqrt on the sfu
  if (spp >= 2) n = int(floor(sqrt(float(spp)) + 0.5));
#ifdef RPU_THIN_LENS
  // the lens disk is spanned by the unit right and up vectors; the focal plane is at
  // focus_distance along the view (0: the distance to look_at)
  const vec3 lens_right = normalize(launch_record.right.xyz);
  const vec3 lens_up = normalize(launch_record.up.xyz);
  float focus_distance = camera_record.focus_distance;
  if (!(focus_distance > 0.0)) focus_distance = length(camera_record.look_at.xyz - camera_record.position.xyz);
#endif
  vec3 sum = vec3(0.0);
  int column = 0, row = 0;
  for (int s = 0; s < spp; ++s) {
    uint stream = rpu_sample_stream(pixel_index, uint(s));
    vec2 offset = vec2(0.5);
    if (spp >= 2) {
      offset.x = rpu_random(stream);
      offset.y = rpu_random(stream);
      if (n * n == spp) offset = (offset + vec2(column, row)) * (1.0 / float(n));
    }
#ifdef RPU_THIN_LENS
    vec2 lens;
    lens.x = rpu_random(stream);
    lens.y = rpu_random(stream);
#else
    // the lens sample: a pinhole camera draws it too, to keep the stream in step
    rpu_random(stream);
    rpu_random(stream);
#endif
    vec2 p = (offset + vec2(pixel)) * (1.0 / vec2(gl_LaunchSizeEXT.xy));
    p = p + p;
    const float x = p.x - 1.0, y = 1.0 - p.y;
    vec3 d = fma(launch_record.right.xyz, vec3(x), launch_record.forward.xyz);
    d = fma(launch_record.up.xyz, vec3(y), d);
#ifdef RPU_THIN_LENS
    // every ray through the lens disk meets the pinhole ray on the focal plane
    vec3 origin = launch_record.origin.xyz;
    if (camera_record.aperture > 0.0) {
      const vec3 focus = fma(d, vec3(focus_distance), origin);
      const float r = camera_record.aperture * sqrt(lens.x);
      const float phi = 6.28318530718 * lens.y;
      origin = fma(lens_right, vec3(r * cos(phi)), origin);
      origin = fma(lens_up, vec3(r * sin(phi)), origin);
      d = focus - origin;
    }
#endif
    d = d * inversesqrt(dot(d, d));
    ray.depth = 0u;
    ray.stream = stream;
#ifndef RPU_THIN_LENS
    const vec3 origin = launch_record.origin.xyz;
#endif
    traceRayEXT(scene_bvh, gl_RayFlagsOpaqueEXT, 0xff, 0, 0, 0, origin, 0.0, d, RPU_INFINITY, 0);
    sum += ray.color;
    if (++column == n) {
      column = 0;
      ++row;
    }
  }
  if (spp >= 2) sum = sum * (1.0 / float(spp));  // one sample is its own mean
  imageStore(framebuffer, ivec2(pixel), vec4(sum, 1.0));
}

#endif
