// Found by the program's `include lib`, not beside the including file.
vec3 tint(float g) { return vec3(g, 0.5 * g, 0.25); }
