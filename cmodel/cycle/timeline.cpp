#include "cycle/timeline.hpp"

#include <algorithm>
#include <ostream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

namespace rpu::cycle {

using nlohmann::json;

Timeline::Timeline(Cycle begin, Cycle end, std::uint64_t max_slices, Sink sink)
    : begin_(begin), end_(end), max_slices_(max_slices), sink_(std::move(sink)) {}

void Timeline::start(Cycle frame_cycles, std::uint64_t frame_slices) {
  base_ = frame_cycles;
  earlier_ = frame_slices;
  slices_ = 0;
  cut_at_.reset();
  open_.clear();
}

void Timeline::add(std::string track, std::string name, Cycle begin, Cycle end) {
  begin = std::max(begin + base_, begin_);
  end = std::min(end + base_, end_);
  if (begin >= end) return;
  // Consecutive cycles of the same activity on a track make one slice.
  for (auto it = open_.rbegin(); it != open_.rend(); ++it) {
    if (it->track == track) {
      if (it->name == name && it->begin + it->cycles == begin) {
        it->cycles = end - it->begin;
        return;
      }
      break;
    }
  }
  if (earlier_ + slices_ >= max_slices_) {
    if (!cut_at_) cut_at_ = begin - base_;
    return;
  }
  ++slices_;
  open_.push_back({std::move(track), std::move(name), begin, end - begin});
  if (open_.size() > kOpenSlices) {
    if (sink_) sink_(open_.front());
    open_.pop_front();
  }
}

void Timeline::flush() {
  for (const TimelineSlice& s : open_) {
    if (sink_) sink_(s);
  }
  open_.clear();
}

// The events go out as they come: the object's other members follow the array.
TimelineWriter::TimelineWriter(const std::filesystem::path& path) : file_(path) {
  file_.stream() << "{\"traceEvents\":[\n";
}

void TimelineWriter::add(const TimelineSlice& s) {
  std::ostream& out = file_.stream();
  auto it = std::find(tracks_.begin(), tracks_.end(), s.track);
  const auto tid = static_cast<int>(it - tracks_.begin());
  if (it == tracks_.end()) {
    tracks_.push_back(s.track);
    const json name = {{"name", "thread_name"}, {"ph", "M"}, {"pid", 0}, {"tid", tid}, {"args", {{"name", s.track}}}};
    out << (first_ ? "" : ",\n") << name.dump();
    first_ = false;
  }
  const json event = {{"name", s.name}, {"ph", "X"}, {"pid", 0}, {"tid", tid}, {"ts", s.begin}, {"dur", s.cycles}};
  out << (first_ ? "" : ",\n") << event.dump();
  first_ = false;
}

std::string timeline_cut_reason(const CycleStats& stats) {
  return fmt::format("cut at cycle {}: the timeline holds at most {} slices, which keeps the file small enough for "
                     "Perfetto to load; the later slices of the window are missing",
                     *stats.timeline_cut_at, stats.timeline_slices);
}

void TimelineWriter::finish(const CycleStats& stats) {
  json other = {{"config", stats.config}, {"time_unit", "1 us shown = 1 cycle"}, {"slices", stats.timeline_slices}};
  if (stats.timeline_cut_at) {
    other["cut_at_cycle"] = *stats.timeline_cut_at;
    other["cut_reason"] = timeline_cut_reason(stats);
  }
  file_.stream() << "\n],\"displayTimeUnit\":\"ns\",\"otherData\":" << other.dump() << "}\n";
  file_.commit();
}

}  // namespace rpu::cycle
