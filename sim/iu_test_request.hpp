#pragma once

#include <cstdint>

#include "functional/tracer.hpp"
#include "rpu/streams.hpp"

namespace rpu::sim {

// The iu_req a traversal unit sends for one of the Tracer's IU tests: the ray's
// registers in the format, the t_best of the walk, the record (iu_cosim's vectors and
// tu_cosim's netlist vectors both check a unit's requests against it).
inline streams::IuReq iu_request_of(const functional::IuTest& t, std::uint32_t tag) {
  streams::IuReq q;
  q.tag = tag;
  for (int i = 0; i < 3; ++i) {
    q.origin[i] = t.ray.origin[i];
    q.direction[i] = t.ray.direction[i];
  }
  q.t_min = t.ray.t_min;
  q.t_best = t.t_best;
  q.kx = static_cast<std::uint32_t>(t.ray.kx);
  q.ky = static_cast<std::uint32_t>(t.ray.ky);
  q.kz = static_cast<std::uint32_t>(t.ray.kz);
  q.shear_x = t.ray.shear_x;
  q.shear_y = t.ray.shear_y;
  q.record = t.record;
  return q;
}

}  // namespace rpu::sim
