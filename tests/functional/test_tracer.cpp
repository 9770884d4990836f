// The golden trace units: the rules of docs/traversal.md, in every format and both
// intersection modes. The kd-tree walk is checked against the same image built as a
// single leaf (every triangle tested, no traversal), which shares no traversal code.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cstdio>
#include <cmath>
#include <limits>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "common/error.hpp"
#include "fp/format.hpp"
#include "functional/scene_image.hpp"
#include "functional/tracer.hpp"
#include "scene/procedural.hpp"
#include "trace_fixtures.hpp"
#include "common/random_vector.hpp"

namespace rpu::functional {
namespace {

struct Case {
  const char* format;
  IsectMode mode;
};

std::string case_name(const ::testing::TestParamInfo<Case>& info) {
  return std::string(info.param.format) + (info.param.mode == IsectMode::kWoop ? "_woop" : "_watertight");
}

class TracerRules : public ::testing::TestWithParam<Case> {
 protected:
  fp::Format format() const { return fp::format_by_name(GetParam().format); }
  IsectMode mode() const { return GetParam().mode; }
  SceneImage image_of(const Scene& scene, int max_depth = 32) const {
    KdBuildConfig config;
    config.max_depth = max_depth;
    config.format = format();
    return make_scene_image(scene, config, mode());
  }
  Tracer tracer_of(const SceneImage& si, int stack_depth = 32) const {
    return Tracer(si.image.bytes, si.layout, format(), stack_depth);
  }
  // Values that are exact in every format under test (E >= 5, M >= 7).
  static bool same_result(const TraceHit& a, const TraceHit& b) {
    return a.hit == b.hit && (!a.hit || (std::bit_cast<std::uint32_t>(a.t) == std::bit_cast<std::uint32_t>(b.t)));
  }
};

TEST_P(TracerRules, AxisParallelRaysWithSignedZerosHitTheFacingCubeFace) {
  const SceneImage si = image_of(test::cube());
  const Tracer tracer = tracer_of(si);
  for (int axis = 0; axis < 3; ++axis) {
    for (double sign : {1.0, -1.0}) {
      for (double zero : {0.0, -0.0}) {
        glm::dvec3 o(0.25, 0.375, -0.125), d(zero);
        o[axis] = -4.0 * sign;  // 4 units out, looking back at the cube
        d[axis] = sign;
        const TraceHit hit = tracer.trace(test::make_ray(o, d), TraceMode::kClosest);
        ASSERT_TRUE(hit.hit) << "axis " << axis << " sign " << sign << " zero " << std::signbit(zero);
        EXPECT_EQ(hit.t, 3.0f);
        // Faces come in triangle pairs: 0-1 x=-1, 2-3 x=+1, 4-5 y=-1, 6-7 y=+1, 8-9 z=-1, 10-11 z=+1.
        EXPECT_EQ(hit.prim / 2, static_cast<std::uint32_t>(2 * axis + (sign > 0 ? 0 : 1)));
        EXPECT_GT(hit.counters.nodes, 0u);
      }
    }
  }
}

TEST_P(TracerRules, NanInfAndZeroDirectionRaysAreDefinedMissesThatFetchNothing) {
  const SceneImage si = image_of(test::cube());
  const Tracer tracer = tracer_of(si);
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  std::vector<TraceRay> bad;
  for (int i = 0; i < 3; ++i) {
    for (float x : {nan, inf, -inf}) {
      TraceRay r = test::make_ray({0, 0, -4}, {0, 0, 1});
      r.origin[i] = x;
      bad.push_back(r);
      r = test::make_ray({0, 0, -4}, {0, 0, 1});
      r.direction[i] = x;
      bad.push_back(r);
    }
  }
  bad.push_back(test::make_ray({0, 0, -4}, {0.0, -0.0, 0.0}));
  TraceRay empty = test::make_ray({0, 0, -4}, {0, 0, 1});
  empty.t_min = 5.0f;
  empty.t_max = 5.0f;
  bad.push_back(empty);
  empty.t_min = nan;
  bad.push_back(empty);
  for (std::size_t i = 0; i < bad.size(); ++i) {
    for (TraceMode m : {TraceMode::kClosest, TraceMode::kAny}) {
      const TraceHit hit = tracer.trace(bad[i], m);
      EXPECT_FALSE(hit.hit) << "ray " << i;
      EXPECT_EQ(hit.counters.nodes, 0u) << "ray " << i;
    }
  }
}

// Traversal = testing every triangle: the same image built as one leaf is the oracle.
void expect_traversal_matches_exhaustive(const TracerRules& self, const Scene& scene,
                                         const std::vector<TraceRay>& rays, const char* what);

TEST_P(TracerRules, OriginsOnSplitPlanesTraceAsAnExhaustiveTest) {
  const Scene scene = make_sphereflake(1, 8);
  const SceneImage si = image_of(scene);
  // Origins exactly on every split plane of the tree, in all directions, including
  // along the plane (a 0 component) and with -0.
  const std::vector<TraceRay> rays = test::split_plane_rays(si, 4000, 5);
  expect_traversal_matches_exhaustive(*this, scene, rays, "split-plane origins");
}

TEST_P(TracerRules, OriginsOnTriangleEdgesAndVerticesTraceAsAnExhaustiveTest) {
  const Scene scene = test::icosphere(2);
  std::vector<TraceRay> rays;
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (std::size_t t = 0; t < scene.triangles.size(); ++t) {
    const glm::dvec3 a(scene.positions[scene.triangles[t].x]), b(scene.positions[scene.triangles[t].y]);
    for (const glm::dvec3& o : {a, 0.5 * (a + b)}) {
      rays.push_back(test::make_ray(o, {u(rng), u(rng), u(rng)}));
      rays.push_back(test::make_ray(o, -o));  // inwards, through the sphere
    }
  }
  expect_traversal_matches_exhaustive(*this, scene, rays, "edge and vertex origins");
}

TEST_P(TracerRules, CameraAndRandomRaysTraceAsAnExhaustiveTest) {
  const Scene scene = make_sphereflake(1, 8);
  std::vector<TraceRay> rays = test::camera_rays(scene, 48, 48);
  const std::vector<TraceRay> random = test::random_rays(scene, 2000, 3);
  rays.insert(rays.end(), random.begin(), random.end());
  expect_traversal_matches_exhaustive(*this, scene, rays, "camera and random rays");
}

void expect_traversal_matches_exhaustive(const TracerRules& self, const Scene& scene,
                                         const std::vector<TraceRay>& rays, const char* what) {
  const fp::Format format = fp::format_by_name(self.GetParam().format);
  KdBuildConfig tree_config;
  tree_config.format = format;
  const SceneImage tree = make_scene_image(scene, tree_config, self.GetParam().mode);
  KdBuildConfig leaf_config;
  leaf_config.format = format;
  leaf_config.max_depth = 0;  // one leaf holding every triangle
  const SceneImage leaf = make_scene_image(scene, leaf_config, self.GetParam().mode);
  ASSERT_EQ(leaf.layout.kd_nodes.count, 1u);
  const Tracer walk(tree.image.bytes, tree.layout, format, 32);
  const Tracer all(leaf.image.bytes, leaf.layout, format, 32);
  // The two can differ only where rounding decides: a hit the format's test accepts a
  // hair outside a triangle (the tree culls the region), two triangles at the same
  // distance, or in the narrowest formats a test so coarse that it accepts a triangle
  // the ray passes nowhere near. The walk is wrong only if the exhaustive answer names a
  // triangle the ray really meets (judged in double precision, within 16 ulps of the
  // format, at least 1e-5) nearer than what the walk reports; every other difference
  // is counted as a precision artifact and must stay rare.
  const double tol = std::max(1e-5, std::ldexp(16.0, -format.fraction_bits));
  int hits = 0, artifacts = 0, failures = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    for (TraceMode m : {TraceMode::kClosest, TraceMode::kAny}) {
      const TraceHit a = walk.trace(rays[i], m), b = all.trace(rays[i], m);
      hits += a.hit;
      if (a.hit == b.hit && (m == TraceMode::kAny || !a.hit || a.t == b.t)) continue;
      bool missed_real_hit = false;
      if (b.hit) {
        const test::DoubleHit exact = test::double_hit(scene, b.prim, rays[i]);
        const bool real = exact.min_barycentric >= -tol && exact.t > 0.0;
        const bool nearer = !a.hit || (m == TraceMode::kClosest &&
                                       exact.t < test::double_hit(scene, a.prim, rays[i]).t - tol * std::max(exact.t, 1.0));
        missed_real_hit = real && nearer;
      }
      artifacts += !missed_real_hit;
      if (missed_real_hit && ++failures <= 5) {
        ADD_FAILURE() << what << " ray " << i << " (" << (m == TraceMode::kAny ? "any" : "closest")
                      << "): o=(" << rays[i].origin[0] << "," << rays[i].origin[1] << "," << rays[i].origin[2]
                      << ") d=(" << rays[i].direction[0] << "," << rays[i].direction[1] << ","
                      << rays[i].direction[2] << ") kd: hit " << a.hit << " t " << a.t << " prim " << a.prim
                      << "; all triangles: hit " << b.hit << " t " << b.t << " prim " << b.prim
                      << ", which the ray really meets, nearer";
      }
    }
  }
  std::printf("%s, %s: %zu rays traced twice (closest, any), %d precision artifacts\n", what, self.GetParam().format, rays.size(), artifacts);
  EXPECT_EQ(failures, 0) << what;
  EXPECT_LE(artifacts, static_cast<int>(2 * rays.size() / 50)) << what << ": precision artifacts must stay rare (2%)";
  EXPECT_GT(hits, 0) << what << ": the rays must hit something";
}

TEST_P(TracerRules, ScalingTheSceneByPowersOfTwoKeepsPrimitiveIds) {
  const Scene base = make_sphereflake(1, 8);
  const std::vector<TraceRay> rays = test::random_rays(base, 1500, 17);
  // The units compute in kd space, where the scene's largest coordinate lies in [1, 2)
  // (docs/traversal.md §1): scaling the scene and the ray origins by 2^k changes only
  // the kd scale exponent, so every format sees the same kd-space rays and geometry
  // and returns the same hits, t scaled by exactly 2^k. Without it the watertight edge
  // products underflow in fp32 below k = -56, and fp16 has no headroom at all.
  constexpr int kLo = -60, kHi = 60;
  std::vector<TraceHit> reference;
  int hits = 0;
  for (int k = kLo; k <= kHi; k += 10) {
    Scene scaled = base;
    const float s = std::ldexp(1.0f, k);
    for (glm::vec3& p : scaled.positions) p *= s;
    const SceneImage si = image_of(scaled);
    const Tracer tracer = tracer_of(si);
    std::vector<TraceHit> found;
    for (TraceRay r : rays) {
      for (float& x : r.origin) x *= s;
      found.push_back(tracer.trace(r, TraceMode::kClosest));
    }
    if (reference.empty()) {
      reference = found;
      for (const TraceHit& h : found) hits += h.hit;
      continue;
    }
    for (std::size_t i = 0; i < rays.size(); ++i) {
      ASSERT_EQ(found[i].hit, reference[i].hit) << "k " << k << " ray " << i;
      if (!found[i].hit) continue;
      EXPECT_EQ(found[i].prim, reference[i].prim) << "k " << k << " ray " << i;
      EXPECT_EQ(found[i].t, std::ldexp(reference[i].t, k - kLo)) << "k " << k << " ray " << i;
      EXPECT_EQ(found[i].u, reference[i].u) << "k " << k << " ray " << i;
      EXPECT_EQ(found[i].v, reference[i].v) << "k " << k << " ray " << i;
    }
  }
  EXPECT_GT(hits, static_cast<int>(rays.size() / 10)) << "the rays must hit the scene";
}

TEST_P(TracerRules, ATreeAsDeepAsTheStackWorksAndAShallowerStackFaults) {
  const Scene scene = make_sphereflake(1, 8);
  const SceneImage si = image_of(scene, 8);
  ASSERT_EQ(si.tree_stats.max_depth, 8);
  const std::vector<TraceRay> rays = test::random_rays(scene, 500, 2);
  const Tracer deep_enough = tracer_of(si, 8);
  for (const TraceRay& r : rays) deep_enough.trace(r, TraceMode::kClosest);
  const Tracer too_shallow = tracer_of(si, 2);
  try {
    for (const TraceRay& r : rays) too_shallow.trace(r, TraceMode::kClosest);
    FAIL() << "expected a stack overflow fault";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("traversal stack overflow"), std::string::npos) << e.what();
  }
}

TEST_P(TracerRules, CountersAddUp) {
  const SceneImage si = image_of(test::icosphere(2));
  const Tracer tracer = tracer_of(si);
  const TraceHit hit = tracer.trace(test::make_ray({0, 0, -3}, {0.01, 0.02, 1}), TraceMode::kClosest);
  ASSERT_TRUE(hit.hit);
  EXPECT_GE(hit.counters.nodes, hit.counters.leaves);
  EXPECT_GE(hit.counters.tests, 1u);
  const TraceHit any = tracer.trace(test::make_ray({0, 0, -3}, {0.01, 0.02, 1}), TraceMode::kAny);
  EXPECT_LE(any.counters.tests, hit.counters.tests);
}

// Packets (docs/traversal.md "Packets"): every ray's hit record and counters are the
// ones its own walk gives, whatever rays share its packet; a packet fetches each node
// once for the rays active there, so coherent rays fetch fewer nodes than their walks.
TEST_P(TracerRules, PacketsGiveEveryRayItsOwnWalksResultAndCounters) {
  const Scene scene = make_sphereflake(1, 8);
  const SceneImage si = image_of(scene);
  const Tracer tracer = tracer_of(si);
  const std::vector<TraceRay> camera = test::camera_rays(scene, 32, 32);
  const std::vector<TraceRay> random = test::random_rays(scene, 1000, 7);
  for (const auto& [what, rays] : {std::pair{"camera", camera}, std::pair{"random", random}}) {
    for (TraceMode mode : {TraceMode::kClosest, TraceMode::kAny}) {
      std::uint64_t fewer_ray_fetches = std::numeric_limits<std::uint64_t>::max();  // the smaller packets'
      for (std::size_t packet : {std::size_t{1}, std::size_t{2}, std::size_t{4}, kMaxPacketRays}) {
        PacketCounters shared;
        std::uint64_t own_nodes = 0;
        int differ = 0;
        // The rays a chunk of eight lanes would trace together.
        for (std::size_t start = 0; start < rays.size(); start += 8) {
          const std::span<const TraceRay> chunk(rays.data() + start, std::min<std::size_t>(8, rays.size() - start));
          std::vector<TraceHit> got(chunk.size());
          tracer.trace_packets(chunk, mode, got, packet, shared);
          for (std::size_t i = 0; i < chunk.size(); ++i) {
            const TraceHit want = tracer.trace(chunk[i], mode);
            own_nodes += want.counters.nodes;
            const bool same = got[i].hit == want.hit && got[i].prim == want.prim &&
                              std::bit_cast<std::uint32_t>(got[i].t) == std::bit_cast<std::uint32_t>(want.t) &&
                              std::bit_cast<std::uint32_t>(got[i].u) == std::bit_cast<std::uint32_t>(want.u) &&
                              std::bit_cast<std::uint32_t>(got[i].v) == std::bit_cast<std::uint32_t>(want.v) &&
                              got[i].counters.nodes == want.counters.nodes &&
                              got[i].counters.leaves == want.counters.leaves &&
                              got[i].counters.tests == want.counters.tests;
            if (!same && ++differ <= 3) {
              ADD_FAILURE() << what << " ray " << start + i << ", packets of " << packet << ": hit " << got[i].hit
                            << " prim " << got[i].prim << " t " << got[i].t << " nodes " << got[i].counters.nodes
                            << " leaves " << got[i].counters.leaves << " tests " << got[i].counters.tests
                            << "; alone: hit " << want.hit << " prim " << want.prim << " t " << want.t << " nodes "
                            << want.counters.nodes << " leaves " << want.counters.leaves << " tests "
                            << want.counters.tests;
            }
          }
        }
        EXPECT_EQ(differ, 0) << what << ", packets of " << packet;
        EXPECT_EQ(shared.restarts, 0u) << what << ", packets of " << packet;
        if (packet == 1) {
          EXPECT_EQ(shared.node_fetches, own_nodes) << what << ": a packet of one fetches what its walk does";
        } else if (std::string(what) == "camera") {
          // Neighbouring camera rays share most nodes, more of them in larger packets.
          EXPECT_LT(shared.node_fetches * 4, own_nodes * 3) << what << ", packets of " << packet;
          EXPECT_LT(shared.node_fetches, fewer_ray_fetches) << what << ", packets of " << packet;
          fewer_ray_fetches = shared.node_fetches;
          std::printf("%s %s, packets of %zu: %llu node fetches for %llu nodes of the rays' own walks\n",
                      what, mode == TraceMode::kAny ? "any" : "closest", packet,
                      static_cast<unsigned long long>(shared.node_fetches), static_cast<unsigned long long>(own_nodes));
        }
      }
    }
  }
}

TEST_P(TracerRules, APacketWhoseRayOverflowsTheStackFaultsAsTheRayAlone) {
  const Scene scene = make_sphereflake(1, 8);
  const SceneImage si = image_of(scene, 8);
  const std::vector<TraceRay> rays = test::random_rays(scene, 500, 2);
  const Tracer too_shallow = tracer_of(si, 2);
  std::vector<TraceHit> out(rays.size());
  PacketCounters shared;
  try {
    too_shallow.trace_packets(rays, TraceMode::kClosest, out, 4, shared);
    FAIL() << "expected a stack overflow fault";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("traversal stack overflow"), std::string::npos) << e.what();
  }
  EXPECT_GT(shared.restarts, 0u);
}

// One packet as the traversal unit walks it (Tracer::trace_packet, the cycle model's
// log): every ray's result is its own walk's; the log's fetches are the packet's, each
// record names the rays that test it, and a packet of one ray logs its walk's events
// with one pass per leaf.
TEST_P(TracerRules, AUnitsPacketLogsItsFetchesTestsAndPasses) {
  using Kind = TraceEvent::Kind;
  const Scene scene = make_sphereflake(1, 8);
  const SceneImage si = image_of(scene);
  const Tracer tracer = tracer_of(si);
  const std::vector<TraceRay> camera = test::camera_rays(scene, 32, 32);
  for (TraceMode mode : {TraceMode::kClosest, TraceMode::kAny}) {
    std::uint64_t fetches = 0, own_nodes = 0;
    int packets = 0;
    for (std::size_t start = 0; start < camera.size();) {
      // The next rays that enter the box with the first one's signs, up to four.
      std::vector<TraceRay> packet;
      std::vector<TraceHit> alone;
      std::uint32_t signs = 0;
      for (; start < camera.size() && packet.size() < 4; ++start) {
        const TraceHit want = tracer.trace(camera[start], mode);
        if (want.counters.nodes == 0) continue;  // misses the box
        std::uint32_t s = 0;
        for (int a = 0; a < 3; ++a) s |= std::uint32_t{std::signbit(camera[start].direction[a])} << a;
        if (!packet.empty() && s != signs) break;
        signs = s;
        packet.push_back(camera[start]);
        alone.push_back(want);
      }
      if (packet.empty()) continue;
      ++packets;
      TraceLog log;
      std::vector<TraceHit> got(packet.size());
      ASSERT_EQ(tracer.trace_packet(packet, mode, got, log), 0u);
      std::uint64_t tests = 0, passes = 0, leaves = 0;
      for (const TraceEvent& e : log.events) {
        fetches += e.kind == Kind::kInner || e.kind == Kind::kLeaf;
        leaves += e.kind == Kind::kLeaf;
        passes += e.kind == Kind::kPop;
        if (e.kind == Kind::kTest) tests += e.rays;
      }
      std::uint64_t own_tests = 0;
      for (std::size_t i = 0; i < packet.size(); ++i) {
        EXPECT_EQ(got[i].hit, alone[i].hit) << "packet " << packets << " ray " << i;
        EXPECT_EQ(got[i].prim, alone[i].prim) << "packet " << packets << " ray " << i;
        EXPECT_EQ(std::bit_cast<std::uint32_t>(got[i].t), std::bit_cast<std::uint32_t>(alone[i].t));
        EXPECT_EQ(got[i].counters.nodes, alone[i].counters.nodes) << "packet " << packets << " ray " << i;
        EXPECT_EQ(got[i].counters.tests, alone[i].counters.tests) << "packet " << packets << " ray " << i;
        own_nodes += alone[i].counters.nodes;
        own_tests += alone[i].counters.tests;
      }
      EXPECT_EQ(tests, own_tests) << "packet " << packets << ": a record's rays are the rays that test it";
      EXPECT_GE(passes, leaves) << "packet " << packets << ": a pass at least after every leaf";
      if (packet.size() == 1) {
        TraceLog own;
        tracer.trace(packet[0], mode, own);
        std::vector<TraceEvent> fetched;
        for (const TraceEvent& e : own.events) {
          if (e.kind != Kind::kPop) fetched.push_back(e);
        }
        std::size_t j = 0;
        for (const TraceEvent& e : log.events) {
          if (e.kind == Kind::kPop) continue;
          ASSERT_LT(j, fetched.size());
          EXPECT_EQ(e.kind, fetched[j].kind);
          EXPECT_EQ(e.address, fetched[j].address);
          ++j;
        }
        EXPECT_EQ(j, fetched.size());
        EXPECT_EQ(passes, leaves) << "a ray alone passes once after each leaf";
      }
    }
    EXPECT_LT(fetches * 4, own_nodes * 3) << "packets of neighbouring camera rays share their fetches";
  }
}

TEST_P(TracerRules, AUnitsPacketWhoseStackFillsWalksItsRaysAgainAlone) {
  const Scene scene = make_sphereflake(1, 8);
  const SceneImage si = image_of(scene, 8);
  const Tracer too_shallow = tracer_of(si, 2);
  const std::vector<TraceRay> camera = test::camera_rays(scene, 16, 16);
  int faulted = 0, walked = 0;
  for (std::size_t i = 0; i + 1 < camera.size(); ++i) {
    // Two rays of the same signs that both enter the box, one of which faults alone.
    const TraceRay pair[2] = {camera[i], camera[i + 1]};
    bool enter = true, same = true;
    std::uint32_t want_faults = 0;
    for (int r = 0; r < 2; ++r) {
      for (int a = 0; a < 3; ++a) same = same && std::signbit(pair[r].direction[a]) == std::signbit(pair[0].direction[a]);
      try {
        enter = enter && too_shallow.trace(pair[r], TraceMode::kClosest).counters.nodes > 0;
      } catch (const Error&) {
        want_faults |= 1u << r;
      }
    }
    if (!enter || !same) continue;
    TraceLog log;
    std::vector<TraceHit> out(2);
    EXPECT_EQ(too_shallow.trace_packet(pair, TraceMode::kClosest, out, log), want_faults) << "rays " << i;
    faulted += want_faults != 0;
    ++walked;
  }
  EXPECT_GT(faulted, 0) << "a stack of 2 overflows on some rays";
  EXPECT_GT(walked, faulted);
}

INSTANTIATE_TEST_SUITE_P(Formats, TracerRules,
                         ::testing::Values(Case{"fp32", IsectMode::kWoop}, Case{"fp32", IsectMode::kWatertight},
                                           Case{"e8m15", IsectMode::kWoop}, Case{"e8m15", IsectMode::kWatertight},
                                           Case{"rpu24", IsectMode::kWoop}, Case{"rpu24", IsectMode::kWatertight},
                                           Case{"bf16", IsectMode::kWoop}, Case{"bf16", IsectMode::kWatertight},
                                           Case{"fp16", IsectMode::kWoop}, Case{"fp16", IsectMode::kWatertight}),
                         case_name);

// Degenerate triangles cannot get a Woop record (the writer refuses them), and the
// watertight test never hits them (det = 0) nor returns NaN.
TEST(TracerDegenerate, WatertightNeverHitsDegenerateTriangles) {
  Scene s;
  s.source = "degenerate";
  s.materials.push_back({});
  s.positions = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0},          // zero area: a point
                 {-1, 0, 0}, {1, 0, 0}, {0.5f, 0, 0},      // collinear
                 {-1, -1, 0}, {1, 1, 0}, {1, 1, 0},        // needle: two vertices coincide
                 {5, 5, 5}, {6, 5, 5}, {5, 6, 5}};          // one real triangle, off to the side
  s.triangles = {{0, 1, 2}, {3, 4, 5}, {6, 7, 8}, {9, 10, 11}};
  s.material_ids.assign(4, 0);
  EXPECT_THROW(make_scene_image(s, KdBuildConfig{}, IsectMode::kWoop), Error);
  const SceneImage si = make_scene_image(s, KdBuildConfig{}, IsectMode::kWatertight);
  for (const char* name : {"fp32", "rpu24", "fp16"}) {
    const Tracer tracer(si.image.bytes, si.layout, fp::format_by_name(name), 32);
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int i = 0; i < 20000; ++i) {
      // y before x: the order gcc drew them in (common/random_vector.hpp says why).
      const double target_y = u(rng), target_x = u(rng), o_y = u(rng), o_x = u(rng);
      const glm::dvec3 target(target_x, target_y, 0.0), o(o_x, o_y, 2.0);
      const TraceHit hit = tracer.trace(test::make_ray(o, target - o), TraceMode::kClosest);
      EXPECT_FALSE(hit.hit && hit.prim != 3) << name << " ray " << i << " hit degenerate prim " << hit.prim;
      EXPECT_FALSE(std::isnan(hit.t) || std::isnan(hit.u) || std::isnan(hit.v)) << name << " ray " << i;
    }
  }
}

// fp32 on host float gives the soft path's bits (docs/numbers.md), through whole rays.
TEST(TracerFastPath, Fp32FastPathEqualsSoftPathBitForBit) {
  const Scene scene = make_sphereflake(1, 8);
  std::vector<TraceRay> rays = test::random_rays(scene, 20000, 23);
  const std::vector<TraceRay> camera = test::camera_rays(scene, 64, 64);
  rays.insert(rays.end(), camera.begin(), camera.end());
  for (IsectMode mode : {IsectMode::kWoop, IsectMode::kWatertight}) {
    const SceneImage si = make_scene_image(scene, KdBuildConfig{}, mode);
    const Tracer fast(si.image.bytes, si.layout, fp::kFp32, 32, true);
    const Tracer soft(si.image.bytes, si.layout, fp::kFp32, 32, false);
    ASSERT_TRUE(fast.uses_fast_path());
    ASSERT_FALSE(soft.uses_fast_path());
    int hits = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
      const TraceHit a = fast.trace(rays[i], TraceMode::kClosest), b = soft.trace(rays[i], TraceMode::kClosest);
      hits += a.hit;
      ASSERT_EQ(a.hit, b.hit) << "ray " << i;
      ASSERT_EQ(a.counters.nodes, b.counters.nodes) << "ray " << i;
      ASSERT_EQ(a.counters.tests, b.counters.tests) << "ray " << i;
      if (!a.hit) continue;
      ASSERT_EQ(a.prim, b.prim) << "ray " << i;
      ASSERT_EQ(std::bit_cast<std::uint32_t>(a.t), std::bit_cast<std::uint32_t>(b.t)) << "ray " << i;
      ASSERT_EQ(std::bit_cast<std::uint32_t>(a.u), std::bit_cast<std::uint32_t>(b.u)) << "ray " << i;
      ASSERT_EQ(std::bit_cast<std::uint32_t>(a.v), std::bit_cast<std::uint32_t>(b.v)) << "ray " << i;
    }
    EXPECT_GT(hits, 1000);
  }
}

}  // namespace
}  // namespace rpu::functional
