#include "device_dram.hpp"

#include <bit>

#include <fmt/format.h>

#include "cosim_core.hpp"

namespace rpu::sim {

void DeviceDram::take(const streams::DramReq& req, std::uint64_t now) {
  constexpr std::uint32_t kWords = streams::kDramLineBytes / 4;
  if (req.addr % streams::kDramLineBytes) {
    throw CosimFailure(fmt::format("memory-port request at {:#010x}, not aligned to {} bytes", req.addr,
                                   streams::kDramLineBytes));
  }
  if (req.write) {
    for (std::uint32_t k = 0; k < kWords; ++k) {
      if (req.wmask >> k & 1) memory_.store32(req.addr + 4 * k, req.data[k]);
    }
    dram_.access(now, req.addr, 4 * static_cast<std::uint32_t>(std::popcount(req.wmask)), true);
    return;
  }
  Pending p{dram_.access(now, req.addr, streams::kDramLineBytes, false), order_++, {}};
  p.rsp.tag = req.tag;
  for (std::uint32_t k = 0; k < kWords; ++k) p.rsp.data[k] = memory_.load32(req.addr + 4 * k);
  pending_.push_back(p);
}

const streams::DramRsp* DeviceDram::offer(std::uint64_t now) const {
  const Pending* best = nullptr;
  for (std::size_t i = 0; i < pending_.size(); ++i) {
    const Pending& p = pending_[i];
    if (p.due <= now && (!best || p.due < best->due || (p.due == best->due && p.order < best->order))) {
      best = &p;
      offered_ = i;
    }
  }
  return best ? &best->rsp : nullptr;
}

void DeviceDram::taken() { pending_.erase(pending_.begin() + static_cast<std::ptrdiff_t>(offered_)); }

}  // namespace rpu::sim
