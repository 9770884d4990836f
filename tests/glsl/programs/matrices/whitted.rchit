#version 460
#extension GL_EXT_ray_tracing : require
layout(location = 0) rayPayloadInEXT vec3 seen;
void main() {
  const vec3 back = gl_ObjectToWorldEXT * vec4(gl_ObjectRayOriginEXT, 1.0) - gl_WorldRayOriginEXT;
  seen = back + gl_WorldToObjectEXT * vec4(1.0, 2.0, 3.0, 0.0);
}
