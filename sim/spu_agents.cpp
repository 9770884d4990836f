#include "spu_agents.hpp"

#include <algorithm>
#include <bit>
#include <cstring>

#include <fmt/format.h>

#include "common/error.hpp"
#include "cosim_core.hpp"
#include "rpu/spec.hpp"

namespace rpu::sim {

namespace mm = spec::memory;

SparseMemory::SparseMemory(std::span<const std::uint8_t> image, std::span<const std::uint8_t> launch_block,
                           std::span<const std::uint8_t> data, std::uint32_t pixels, std::uint32_t stack_bytes_total)
    : framebuffer_end_(mm::kDeviceFramebufferBase + pixels * mm::kFramebufferBytesPerPixel),
      stack_end_(mm::kDeviceStackBase + stack_bytes_total) {
  put(mm::kDeviceImageBase, image);
  put(mm::kDeviceLaunchBase, launch_block);
  put(mm::kDeviceDataBase, data);
}

void SparseMemory::put(std::uint32_t address, std::span<const std::uint8_t> bytes) {
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    const std::uint32_t a = address + static_cast<std::uint32_t>(i);
    auto& page = pages_[a / kPage];
    if (page.empty()) page.assign(kPage, 0);
    page[a % kPage] = bytes[i];
  }
}

std::uint32_t SparseMemory::load32(std::uint32_t address) const {
  std::uint32_t v = 0;
  for (std::uint32_t i = 0; i < 4; ++i) {
    const auto it = pages_.find((address + i) / kPage);
    if (it != pages_.end()) v |= std::uint32_t{it->second[(address + i) % kPage]} << (8 * i);
  }
  return v;
}

void SparseMemory::store32(std::uint32_t address, std::uint32_t value) {
  const bool framebuffer = address >= mm::kDeviceFramebufferBase && address < framebuffer_end_;
  const bool stack = address >= mm::kDeviceStackBase && address < stack_end_;
  if (!framebuffer && !stack) {
    throw CosimFailure(fmt::format("the core writes {:#010x} at {:#010x}, outside the framebuffer and the stacks", value,
                                   address));
  }
  const std::uint8_t bytes[4] = {static_cast<std::uint8_t>(value), static_cast<std::uint8_t>(value >> 8),
                                 static_cast<std::uint8_t>(value >> 16), static_cast<std::uint8_t>(value >> 24)};
  put(address, bytes);
}

std::vector<std::uint8_t> SparseMemory::read(std::uint32_t address, std::uint32_t bytes) const {
  std::vector<std::uint8_t> out(bytes, 0);
  for (std::uint32_t i = 0; i < bytes; ++i) {
    const auto it = pages_.find((address + i) / kPage);
    if (it != pages_.end()) out[i] = it->second[(address + i) % kPage];
  }
  return out;
}

namespace {

std::uint64_t due(std::uint64_t cycle, AgentTiming t, std::mt19937_64& rng) {
  return cycle + static_cast<std::uint64_t>(t.latency) +
         (t.jitter > 0 ? std::uniform_int_distribution<std::uint64_t>(0, static_cast<std::uint64_t>(t.jitter))(rng) : 0);
}

// The pending answer whose delay ended first (the earliest taken among equals).
template <class P>
const P* earliest(const std::vector<P>& pending, std::uint64_t cycle, std::size_t& index) {
  const P* best = nullptr;
  for (std::size_t i = 0; i < pending.size(); ++i) {
    if (pending[i].due <= cycle && (!best || pending[i].due < best->due)) {
      best = &pending[i];
      index = i;
    }
  }
  return best;
}

}  // namespace

void CachePortServer::take(const streams::CacheReq& req, std::uint64_t cycle) {
  constexpr std::uint32_t words = streams::kMemLineBytes / 4;
  if (req.addr % streams::kMemLineBytes) {
    throw CosimFailure(fmt::format("cache request at {:#010x}, not aligned to {} bytes", req.addr,
                                   streams::kMemLineBytes));
  }
  if (req.write) {
    for (std::uint32_t k = 0; k < words; ++k) {
      if (req.wmask >> k & 1) memory_.store32(req.addr + 4 * k, req.data[k]);
    }
    return;
  }
  Pending p{due(cycle, timing_, rng_), {}};
  p.rsp.tag = req.tag;
  for (std::uint32_t k = 0; k < words; ++k) p.rsp.data[k] = memory_.load32(req.addr + 4 * k);
  pending_.push_back(p);
}

const streams::CacheRsp* CachePortServer::offer(std::uint64_t cycle) const {
  const Pending* p = earliest(pending_, cycle, offered_);
  return p ? &p->rsp : nullptr;
}

void CachePortServer::taken() { pending_.erase(pending_.begin() + static_cast<std::ptrdiff_t>(offered_)); }

void RayServer::take(const streams::TraceReq& req, std::uint64_t cycle) {
  if (packet_open_ && (req.pc != packet_pc_ || req.tag <= packet_tag_)) {
    throw CosimFailure(fmt::format("trace_req: a ray of pc {} (tag 0x{:x}) before the packet_end of the trace at pc {} "
                            "(last tag 0x{:x}): a chunk's rays must end their packet",
                            req.pc, req.tag, packet_pc_, packet_tag_));
  }
  packet_open_ = !req.packet_end;
  packet_pc_ = req.pc;
  packet_tag_ = req.tag;
  functional::TraceRay ray;
  for (int i = 0; i < 3; ++i) {
    ray.origin[static_cast<std::size_t>(i)] = std::bit_cast<float>(req.origin[static_cast<std::size_t>(i)]);
    ray.direction[static_cast<std::size_t>(i)] = std::bit_cast<float>(req.direction[static_cast<std::size_t>(i)]);
  }
  ray.t_min = std::bit_cast<float>(req.t_min);
  ray.t_max = std::bit_cast<float>(req.t_max);
  Pending p{due(cycle, timing_, rng_), {}};
  p.rsp.tag = req.tag;
  p.rsp.pc = req.pc;
  try {
    const functional::TraceHit hit =
        tracer_.trace(ray, req.any_hit ? functional::TraceMode::kAny : functional::TraceMode::kClosest);
    p.rsp.hit = hit.hit;
    if (hit.hit) {
      p.rsp.t = std::bit_cast<std::uint32_t>(hit.t);
      p.rsp.u = std::bit_cast<std::uint32_t>(hit.u);
      p.rsp.v = std::bit_cast<std::uint32_t>(hit.v);
      p.rsp.prim = hit.prim;
    }
  } catch (const Error&) {
    p.rsp.fault = 1;
  }
  pending_.push_back(p);
  ++rays_;
}

const streams::TraceRsp* RayServer::offer(std::uint64_t cycle) const {
  const Pending* p = earliest(pending_, cycle, offered_);
  return p ? &p->rsp : nullptr;
}

void RayServer::taken() { pending_.erase(pending_.begin() + static_cast<std::ptrdiff_t>(offered_)); }

}  // namespace rpu::sim
