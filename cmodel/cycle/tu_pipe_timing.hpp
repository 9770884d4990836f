// The timing of a pipelined traversal unit (rtl/rpu_tu_pipe.sv, docs/cycle-model.md
// "Traversal and intersection units"): its ray slots share one memory port and one
// node-step pipeline, and its leaves stream tests to the IUs. Stepped cycle by cycle
// like the RTL, with the rays' walks taken from the tracer's logs: set-up engines,
// slot phases, the port's priority (record lines, then refs, then nodes), the lines in
// flight answered in order or by tag, the record jobs and buffers, the test table, the pop pass in cycles no
// inner node enters, the finish stage and the response arbiter. The chip's cycle
// model and tu_cosim's comparison with the RTL ray unit (--cycle-model) run this code.
#pragma once

#include <cstdint>
#include <deque>
#include <queue>
#include <span>
#include <vector>

#include "cycle/ray_unit_timing.hpp"
#include "functional/tracer.hpp"
#include "memory/memory_image.hpp"

namespace rpu::cycle {

// A configuration's pipelined unit (spec/config_keys.toml tu_*, spec/latencies.toml
// [tu] pipe_*) in one intersection mode; of() is where its values come from.
struct PipeCosts {
  std::uint32_t slots, setups;
  std::uint32_t lines;  // lines in flight on the memory port (the unit's line table, 2^LineTagBits)
  bool by_tag;          // answers taken as they come; else in request order (rpu_inorder_port)
  Cycle handoff;             // a set-up engine: from taking a ray to offering it to a slot
  Cycle node;                // a node's line taken to its slot's next fetch
  Cycle memory_wait;         // beyond the line source's answer (the chip's port registers)
  Cycle iu_latency, iu_interval, iu_wait;
  std::uint32_t record_lines;  // an intersection record's memory lines
  std::uint32_t packet = 1;    // rays a slot walks together (rpu_tu_pipe's Packet)

  // The chip's unit: as many lines as the tag bits its cache arbiter leaves it name.
  static PipeCosts of(const spec::HardwareConfig& config, IsectMode mode);
};

// What a unit with packets knows of a ray as it comes in (tu_req): whether it ends its
// input packet, and, for forming packets after set-up, its direction signs (inv's sign
// bits in the format, bit a: axis a) and mode.
struct PacketRay {
  bool packet_end = true;
  std::uint32_t signs = 0;
  bool any_hit = false;
};

// The walk of a packet a unit with packets closes: the rays' ids in the packet's order,
// its log to fill (functional::Tracer::trace_packet's).
class PacketWalks {
 public:
  virtual ~PacketWalks() = default;
  virtual void walk(std::span<const std::uint32_t> rays, functional::TraceLog& log) = 0;
};

// The unit stepped a cycle at a time; its caller offers it rays and takes its answers
// (the chip's PipeUnitTiming, tu_cosim's harness). With costs.packet > 1 a slot walks a
// packet of rays, whose walk `walks` gives when the packet closes.
class PipeTraversalUnit {
 public:
  PipeTraversalUnit(const PipeCosts& costs, LineSource& lines, std::span<IuTimer> ius, PacketWalks* walks = nullptr);

  // Whether a ray offered in the next cycle is taken (a set-up engine's buffer has room).
  bool ready() const;
  // A ray taken in the cycle the next tick() runs; `log` outlives its walk (a ray that
  // misses the scene box has an empty one).
  void take(std::uint32_t ray, const functional::TraceLog& log, const PacketRay& packet = {});
  // Runs cycle `now` (each cycle once, in order); appends the rays answered in it.
  void tick(Cycle now, std::vector<std::uint32_t>& answered);
  bool idle() const { return rays_ == 0; }

  // Slot-cycles: busy (a node in the pipeline, a leaf's end, the finish), waiting for
  // memory (a node to fetch or on its way), waiting for the IU (a leaf's tests); and
  // the walks' counts.
  TraversalUnitTime time;

 private:
  enum class Phase : std::uint8_t { kFree, kForm, kReady, kNode, kLeaf, kLeafEnd, kPop, kDone, kFinish };
  enum class Kind : std::uint8_t { kNode, kRef, kRecord };
  struct Ray {
    std::uint32_t id = 0;
    const functional::TraceLog* log = nullptr;
    PacketRay packet{};
    std::uint32_t seq = 0;  // its input packet
  };
  struct Engine {
    Ray out, skid;  // rpu_skid_buf's two registers
    bool out_valid = false, skid_valid = false;
    bool working = false;
    Ray ray;
    Cycle offer_at = 0;  // offers its ray (or answers a miss) from here
  };
  struct Slot {
    Phase phase = Phase::kFree;
    Ray ray;                                    // its (first) ray
    std::vector<std::uint32_t> rays;            // its rays, in the packet's order
    functional::TraceLog walk;                  // with packets: the packet's walk
    const functional::TraceLog* log = nullptr;  // the walk it replays: its ray's, or `walk`
    std::uint32_t answered = 0;                 // its rays answered
    std::size_t next = 0;  // the log's next event
    std::size_t refs = 0;  // the leaf's first ref event
    std::uint32_t count = 0, k = 0, pending = 0;
    std::uint32_t rec_k = 0, test_k = 0;  // its leaf's next record to read, next test to send
    bool stepping = false;  // its node's line is in the pipeline
  };
  struct Line {
    Cycle at;  // answered from here (in order: once every older line is)
    Kind kind;
    bool leaf;
    std::uint32_t slot, record;  // a ref's: its record's address; a record line's: its buffer
    std::uint32_t k = 0;         // a ref's list index
    std::uint32_t tests = 1;     // a ref's: the rays that test its record
  };
  struct Job {
    bool busy = false;
    std::uint32_t slot = 0, k = 0, record = 0;
    std::uint32_t tests = 1;  // the rays that test the record
  };
  struct RecordBuffer {
    bool busy = false;
    std::uint32_t got = 0;  // its lines answered
    Job job{};
    std::uint32_t sent = 0;  // its tests gone to the IU
  };
  struct Step {
    Cycle at;  // the decide stage
    std::uint32_t slot;
    bool pop;
  };
  struct Answer {
    Cycle at;
    std::uint32_t slot;
    bool operator>(const Answer& o) const { return at > o.at; }
  };
  // rpu_rr_arbiter: the first valid input after the last granted; a grant presented
  // and not taken is held.
  struct RoundRobin {
    std::uint32_t inputs = 1, last = 0, held = 0;
    bool hold = false;
    int grant(std::uint64_t valid) const;
    void update(int grant, bool ready);
  };
  // A cycle's grants, decided on the state at its start (bit s of a mask: slot s).
  struct Grants {
    std::uint64_t free = 0, ready = 0, leaf_end = 0, done = 0, refs = 0, leaf_over = 0;
    std::uint64_t missing = 0;  // engines answering a ray that misses the scene box
    int start = -1;             // the engine whose ray a slot takes
    bool give = false;
    bool join = false;          // ... into the packet being formed
    bool close_formed = false;  // the packet being formed closes
    bool form_ends = false;     // ... as no ray of its input packet is left in set-up
    int ref = -1, fetch = -1;   // the slots whose ref, whose node the port reads
    bool ref_issue = false, fetched = false, record_go = false;
    int job = -1;       // the job whose record line the port may read
    int job_free = -1;  // the job-table entry a ref answered takes
    bool line_taken = false;
    std::size_t line_at = 0;  // the answered line's place in order_
    Line line{};
    int pop = -1;
    bool pop_enter = false;
    IuTimer* iu = nullptr;  // the IU free first
    int test_buffer = -1;   // the record buffer whose test goes to it
    bool test_issue = false, answer = false, decide = false;
    int rsp = -1, fin = -1;
    bool fin_rsp_taken = false, fin_take = false;
  };

  std::uint64_t grant_engines(Cycle now, Grants& g) const;
  void grant_slots(Grants& g);
  void grant_start(std::uint64_t offering, Grants& g);
  void grant_port(Grants& g);
  void grant_line(Cycle now, Grants& g) const;
  int whole_buffer() const;
  void grant_pop(Grants& g);
  void grant_test(Cycle now, Grants& g);
  void grant_response(Grants& g);
  std::size_t incoming_engine();
  void set_up(Cycle now, const Grants& g, std::vector<std::uint32_t>& answered);
  void fetch(Cycle now, const Grants& g);
  void take_line(Cycle now, const Grants& g);
  void test(Cycle now, const Grants& g);
  void pop(Cycle now, const Grants& g);
  void step(const Grants& g);
  void respond(const Grants& g, std::vector<std::uint32_t>& answered);
  void close(Slot& sl);
  bool forming_ends() const;

  // rpu_tu_pipe's LeafDepth, Tests and Records, as rpu_ray_unit builds it: refs fetched
  // ahead of their tests, tests in flight to the IUs, records being read.
  static constexpr std::uint32_t kLeafDepth = 16, kTests = 32, kRecords = 4;

  PipeCosts costs_;
  LineSource& lines_;
  std::span<IuTimer> ius_;
  PacketWalks* walks_;
  std::vector<Engine> engines_;
  std::vector<Slot> slots_;
  Ray incoming_;
  bool has_incoming_ = false;
  std::deque<Line> order_;  // the lines in flight, in request order
  std::vector<Job> jobs_;  // rpu_tu_pipe's job table
  std::vector<RecordBuffer> buffers_;
  std::uint32_t sent_ = 0, send_job_ = 0, fill_buffer_ = 0, work_ = 0, tests_busy_ = 0;
  std::priority_queue<Answer, std::vector<Answer>, std::greater<>> answers_;
  std::deque<Step> steps_;
  RoundRobin start_rr_, fetch_rr_, ref_rr_, pop_rr_, fin_rr_, rsp_rr_;
  bool fin_valid_ = false;
  std::uint32_t fin_slot_ = 0;
  std::uint32_t rays_ = 0;  // taken and not answered
  // With packets: the input packet taking rays (and whether the ray taken in this cycle
  // ends it), the record buffer whose tests have begun, and the packet being formed.
  std::uint32_t in_seq_ = 0;
  bool end_taken_ = false;
  bool test_hold_ = false;
  std::uint32_t test_held_ = 0;
  bool form_open_ = false;
  std::uint32_t form_slot_ = 0, form_seq_ = 0, form_signs_ = 0;
  bool form_any_hit_ = false;
};

// A pipelined unit of the chip: a PipeTraversalUnit that takes a ray from the dispatch
// in a cycle a set-up engine has room (RayDispatch::send: one a cycle to all units),
// stepped in every cycle in which it holds a ray or rays wait; `index` among the chip's
// units. With packets (costs.packet > 1), `tracer` walks each packet it closes.
class PipeUnitTiming final : public RayUnitTiming, private PacketWalks {
 public:
  PipeUnitTiming(const PipeCosts& costs, LineSource& lines, std::span<IuTimer> ius, Ports& ports,
                 std::size_t index = 0, const functional::Tracer* tracer = nullptr)
      : unit_(costs, lines, ius, tracer ? this : nullptr), ports_(ports), slots_(costs.slots),
        packet_(costs.packet), tracer_(tracer), index_(index) {}

  Cycle ray_waiting(Cycle at) override { return at; }
  Cycle advance(Cycle now) override;
  bool takes_ray() const override { return unit_.ready(); }
  TraversalUnitTime time(Cycle end) const override;

 private:
  void walk(std::span<const std::uint32_t> rays, functional::TraceLog& log) override;

  PipeTraversalUnit unit_;
  Ports& ports_;
  std::uint32_t slots_;
  std::uint32_t packet_;
  const functional::Tracer* tracer_;
  std::size_t index_;
  std::vector<functional::TraceRay> packet_rays_;
  std::vector<functional::TraceHit> out_;
  std::deque<Ray> rays_;  // by the id the unit answers with; grows at the back only: the unit holds pointers to their logs
  std::vector<std::uint32_t> free_ids_;
  std::vector<std::uint32_t> answered_;
};

}  // namespace rpu::cycle
