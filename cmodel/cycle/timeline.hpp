// The units' activity as a timeline (docs/cycle-model.md "Statistics", rpu render
// --trace): what each core, traversal unit and intersection unit did in which cycles,
// recorded while the frame runs and written as Chrome / Perfetto trace JSON.
#pragma once

#include <cstdint>
#include <deque>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "common/output_file.hpp"
#include "cycle/cycle_stats.hpp"

namespace rpu::cycle {

// One bar of the timeline: a unit did `name` from `begin` for `cycles` cycles.
struct TimelineSlice {
  std::string track;  // "core 0", "TU 1", "IU 0"
  std::string name;
  Cycle begin = 0, cycles = 0;
};

// A launch's slices within the frame's window [begin, end): consecutive cycles of one
// activity on a track make one slice, which goes to the sink once no later cycle can
// extend it, so that the frame keeps only a few. At `max_slices` in the frame the rest
// of the window is cut.
class Timeline {
 public:
  using Sink = std::function<void(const TimelineSlice&)>;

  // Records nothing.
  Timeline() = default;
  Timeline(Cycle begin, Cycle end, std::uint64_t max_slices, Sink sink);

  // Whether it records anything (callers skip naming slices when not).
  bool enabled() const { return end_ > begin_; }
  // A launch starts: pass 1 of a selected frame continues pass 0's timeline, which
  // took `frame_cycles` and `frame_slices`.
  void start(Cycle frame_cycles, std::uint64_t frame_slices);
  // `track` did `name` in the launch's cycles [begin, end).
  void add(std::string track, std::string name, Cycle begin, Cycle end);
  // The launch has ended: the slices still open go to the sink.
  void flush();

  // The launch's slices, and where (in its cycles) the first one left out began.
  std::uint64_t slices() const { return slices_; }
  std::optional<Cycle> cut_at() const { return cut_at_; }

 private:
  // The latest slices, which a later one on the same track may still extend.
  static constexpr std::size_t kOpenSlices = 8;

  Cycle begin_ = 0, end_ = 0;
  std::uint64_t max_slices_ = 0;
  Sink sink_;
  Cycle base_ = 0;             // the launch's cycle 0 in the frame
  std::uint64_t earlier_ = 0;  // the frame's slices before the launch
  std::uint64_t slices_ = 0;
  std::optional<Cycle> cut_at_;
  std::deque<TimelineSlice> open_;
};

// The timeline as Chrome / Perfetto trace JSON (one microsecond shown per cycle),
// streamed to the file slice by slice during the frame, so that memory does not grow
// with the window. The file replaces `path` at finish(), not before.
class TimelineWriter {
 public:
  // rpu::Error naming the path if its temporary cannot be created.
  explicit TimelineWriter(const std::filesystem::path& path);
  void add(const TimelineSlice& slice);
  // The metadata ("otherData": the config, and where and why a cut timeline was cut),
  // then the file is committed; rpu::Error if any write failed.
  void finish(const CycleStats& stats);

 private:
  OutputFile file_;
  std::vector<std::string> tracks_;
  bool first_ = true;
};

// Why the frame's timeline was cut (stats.timeline_cut_at is set), for the file's
// metadata and the terminal.
std::string timeline_cut_reason(const CycleStats& stats);

}  // namespace rpu::cycle
