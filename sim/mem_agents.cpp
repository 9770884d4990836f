#include "mem_agents.hpp"

#include <algorithm>
#include <bit>

#include <fmt/format.h>

namespace rpu::sim {

std::uint32_t WordMemory::initial_word(std::uint32_t address) {
  // A multiplicative hash: neighbouring words and lines differ.
  std::uint32_t x = address * 0x9e3779b1u;
  return x ^ (x >> 15) ^ 0x5bd1e995u;
}

std::uint32_t WordMemory::load(std::uint32_t address) const {
  const auto it = words_.find(address);
  return it == words_.end() ? initial_word(address) : it->second;
}

void WordMemory::store(std::uint32_t address, std::uint32_t value) { words_[address] = value; }

std::vector<std::uint32_t> WordMemory::written() const {
  std::vector<std::uint32_t> out;
  out.reserve(words_.size());
  for (const auto& [address, value] : words_) out.push_back(address);
  std::sort(out.begin(), out.end());
  return out;
}

AddressPicker::AddressPicker(std::size_t cache, const streams::CacheGeometry& geometry, std::mt19937_64& rng)
    : base_(static_cast<std::uint32_t>(cache) << kCacheSpanBits), geometry_(geometry) {
  const std::uint32_t sets = cache_sets(geometry);
  std::vector<std::uint32_t> all(sets);
  for (std::uint32_t s = 0; s < sets; ++s) all[s] = s;
  std::shuffle(all.begin(), all.end(), rng);
  hot_sets_.assign(all.begin(), all.begin() + std::min<std::size_t>(4, sets));
}

std::uint32_t AddressPicker::pick(std::mt19937_64& rng) const {
  const std::uint32_t sets = cache_sets(geometry_);
  std::uint32_t line;
  if (std::bernoulli_distribution(0.9)(rng)) {
    const std::uint32_t set = hot_sets_[std::uniform_int_distribution<std::size_t>(0, hot_sets_.size() - 1)(rng)];
    line = std::uniform_int_distribution<std::uint32_t>(0, geometry_.ways + 1)(rng) * sets + set;
  } else {
    line = std::uniform_int_distribution<std::uint32_t>(0, 8 * sets * geometry_.ways - 1)(rng);
  }
  const std::uint32_t piece =
      std::uniform_int_distribution<std::uint32_t>(0, streams::kDramLineBytes / streams::kMemLineBytes - 1)(rng);
  return base_ + line * streams::kDramLineBytes + piece * streams::kMemLineBytes;
}

DramServer::DramServer(const spec::DramConfig& config)
    : dram_(config), reads_("dram_req read", "dram_rsp", static_cast<int>(streams::kDramTagBits)) {}

void DramServer::take(const streams::DramReq& req, std::uint64_t cycle) {
  constexpr std::uint32_t words = streams::kDramLineBytes / 4;
  if (req.addr % streams::kDramLineBytes) {
    throw CosimFailure(fmt::format("dram_req at {:#010x}, not aligned to {} bytes", req.addr, streams::kDramLineBytes));
  }
  const std::size_t cache = req.tag >> streams::kDramMshrBits;
  if (cache >= kMemCaches || cache_of(req.addr) != cache) {
    throw CosimFailure(fmt::format("dram_req {} at {:#010x} tagged {:#04x} (cache {}): the address is cache {}'s",
                                   req.write ? "write" : "read", req.addr, req.tag, cache, cache_of(req.addr)));
  }
  if (req.write) {
    for (std::uint32_t k = 0; k < words; ++k) {
      if (req.wmask >> k & 1) memory_.store(req.addr + 4 * k, req.data[k]);
    }
    dram_.access(cycle, req.addr, 4 * static_cast<std::uint32_t>(std::popcount(req.wmask)), true);
    ++counts_[cache].writes;
    if (std::popcount(req.wmask) == static_cast<int>(words)) ++counts_[cache].line_writes;
    return;
  }
  if (req.wmask != 0) {
    throw CosimFailure(fmt::format("dram_req read at {:#010x} with write mask {:#06x}", req.addr, req.wmask));
  }
  Read r;
  r.due = dram_.access(cycle, req.addr, streams::kDramLineBytes, false);
  r.serial = serial_++;
  r.addr = req.addr;
  r.rsp.tag = req.tag;
  for (std::uint32_t k = 0; k < words; ++k) r.rsp.data[k] = memory_.load(req.addr + 4 * k);
  reads_.add(req.tag, r);
  in_flight_tags_.push_back(req.tag);
  ++counts_[cache].reads;
  bool& before = fetched_[req.addr];
  if (before) ++counts_[cache].refetches;
  before = true;
}

const streams::DramRsp* DramServer::offer(std::uint64_t cycle, bool may_offer) {
  if (!offering_ && may_offer) {
    const Read* best = nullptr;
    for (const std::uint32_t tag : in_flight_tags_) {
      const Read* r = reads_.find(tag);
      if (r->due <= cycle && (!best || r->due < best->due || (r->due == best->due && r->serial < best->serial))) {
        best = r;
        offered_tag_ = tag;
      }
    }
    offering_ = best != nullptr;
  }
  return offering_ ? &reads_.find(offered_tag_)->rsp : nullptr;
}

void DramServer::taken() {
  reads_.take(offered_tag_);
  std::erase(in_flight_tags_, offered_tag_);
  offering_ = false;
}

bool DramServer::reading(std::uint32_t line_address) const {
  for (const std::uint32_t tag : in_flight_tags_) {
    if (reads_.find(tag)->addr == line_address) return true;
  }
  return false;
}

bool LruReference::read(std::uint32_t line) {
  std::list<std::uint32_t>& set = sets_[line % sets_.size()];
  const auto it = std::find(set.begin(), set.end(), line);
  const bool hit = it != set.end();
  if (hit) set.erase(it);
  set.push_front(line);
  if (set.size() > geometry_.ways) set.pop_back();
  return hit;
}

}  // namespace rpu::sim
