// The rays of the shader cores onto the ray units (docs/chip.md "Top"): a ray
// (trace_req_t) from a core goes to the lowest ray unit that takes it and has room in
// its table of UnitRays rays in flight; the ray's tag at the unit is its entry there, and
// the unit's answer, by that tag, goes back to the core the entry's request names, as a
// trace_rsp_t with the request's tag and pc. One ray a cycle: from the next core after
// the last one served that has a unit to send to; the units' answers to one core are
// served round robin too. UnitRays = 1 gives a walker unit one ray at a time. With
// Packets, the rays of a chunk's trace (up to the one with packet_end) go to one unit one
// after another, as a packet: once a core's ray without packet_end is sent to a unit,
// that core's rays go to that unit and no other core's do until the packet's last; the
// other cores meanwhile send to the other units.
module rpu_ray_dispatch #(
  parameter int unsigned Cores    = 1,
  parameter int unsigned Units    = 1,
  parameter int unsigned UnitRays = 1,
  parameter int unsigned Packets  = 0,  // 1: a chunk's rays go to one unit as a packet
  localparam int unsigned CoreIdx = Cores > 1 ? $clog2(Cores) : 1,
  localparam int unsigned UnitIdx = Units > 1 ? $clog2(Units) : 1,
  localparam int unsigned RayIdx  = UnitRays > 1 ? $clog2(UnitRays) : 1
) (
  input  logic                                  clk_i,
  input  logic                                  rst_ni,

  // From the cores, one port each.
  input  logic [Cores-1:0]                      core_req_valid_i,
  output logic [Cores-1:0]                      core_req_ready_o,
  input  logic [Cores*rpu_pkg::TraceReqBits-1:0] core_req_i,
  output logic [Cores-1:0]                      core_rsp_valid_o,
  input  logic [Cores-1:0]                      core_rsp_ready_i,
  output logic [Cores*rpu_pkg::TraceRspBits-1:0] core_rsp_o,

  // To the ray units, one port each.
  output logic [Units-1:0]                      unit_req_valid_o,
  input  logic [Units-1:0]                      unit_req_ready_i,
  output logic [Units*rpu_pkg::TuReqBits-1:0]   unit_req_o,
  input  logic [Units-1:0]                      unit_rsp_valid_i,
  output logic [Units-1:0]                      unit_rsp_ready_o,
  input  logic [Units*rpu_pkg::TuRspBits-1:0]   unit_rsp_i,

  output logic                                  idle_o  // no ray in a unit
);

  localparam int unsigned TagBits = rpu_pkg::TraceTagBits;
  // A ray's tag names its core in the high bits (spec/streams.toml trace_tag_bits).
  localparam int unsigned CoreLsb = TagBits - rpu_pkg::CoreBits;

  localparam int unsigned Entries = Units * UnitRays;

  // What each unit's rays must carry back: the request's tag and pc, per entry.
  logic [Entries-1:0]         busy_d, busy_q;
  logic [Entries*TagBits-1:0] tag_d, tag_q;
  logic [Entries*32-1:0]      pc_d, pc_q;

  // ---------------------------------------------------------------------------------
  // Requests: the next core after the last one served that has a unit to send to: the
  // unit its packet holds, or else the lowest unit with room that no other core's packet
  // holds.
  // ---------------------------------------------------------------------------------
  logic [CoreIdx-1:0] last_core_d, last_core_q;
  // Per core, a packet being sent: the rest of it goes to its unit.
  logic [Cores-1:0]         locked_d, locked_q;
  logic [Cores*UnitIdx-1:0] lock_unit_d, lock_unit_q;
  logic [Units-1:0]         room;       // the unit takes a ray and has a free entry
  logic [Units*RayIdx-1:0]  free_entry; // its lowest free entry
  always_comb begin : unit_room
    room       = '0;
    free_entry = '0;
    for (int u = 0; u < Units; u++) begin
      for (int r = UnitRays - 1; r >= 0; r--) begin
        if (!busy_q[u*UnitRays + r] && unit_req_ready_i[u]) begin
          room[u]                          = 1'b1;
          free_entry[RayIdx*u +: RayIdx]   = RayIdx'(r);
        end
      end
    end
  end

  // Per core and unit: another core's packet holds the unit.
  logic [Cores*Units-1:0]   held;
  always_comb begin : held_units
    held = '0;
    for (int c = 0; c < Cores; c++) begin
      for (int o = 0; o < Cores; o++) begin
        if (o != c && locked_q[o]) held[c*Units + 32'(lock_unit_q[UnitIdx*o +: UnitIdx])] = 1'b1;
      end
    end
  end

  logic [Cores-1:0]         can_send;   // per core: a ray and a unit for it
  logic [Cores*UnitIdx-1:0] target;     // per core: that unit
  always_comb begin : core_targets
    can_send = '0;
    target   = '0;
    for (int c = 0; c < Cores; c++) begin
      if (locked_q[c]) begin
        can_send[c]                  = core_req_valid_i[c] && room[32'(lock_unit_q[UnitIdx*c +: UnitIdx])];
        target[UnitIdx*c +: UnitIdx] = lock_unit_q[UnitIdx*c +: UnitIdx];
      end else begin
        for (int u = Units - 1; u >= 0; u--) begin
          if (room[u] && !held[c*Units + u]) begin
            can_send[c]                  = core_req_valid_i[c];
            target[UnitIdx*c +: UnitIdx] = UnitIdx'(u);
          end
        end
      end
    end
  end

  logic               send;
  logic [CoreIdx-1:0] core;
  logic [UnitIdx-1:0] unit;
  logic [RayIdx-1:0]  entry;  // the unit's lowest free entry
  always_comb begin : pick_core
    send = 1'b0;
    core = '0;
    for (int k = Cores; k >= 1; k--) begin
      if (can_send[(32'(last_core_q) + k) % Cores]) begin
        send = 1'b1;
        core = CoreIdx'((32'(last_core_q) + k) % Cores);
      end
    end
  end
  assign unit  = target[UnitIdx*core +: UnitIdx];
  assign entry = free_entry[RayIdx*unit +: RayIdx];

  rpu_pkg::trace_req_t req;
  rpu_pkg::tu_req_t    unit_req;
  assign req  = core_req_i[rpu_pkg::TraceReqBits*core +: rpu_pkg::TraceReqBits];
  always_comb begin : unit_request
    unit_req           = '0;
    unit_req.origin    = req.origin;
    unit_req.direction = req.direction;
    unit_req.t_min     = req.t_min;
    unit_req.t_max     = req.t_max;
    unit_req.any_hit   = req.any_hit;
    unit_req.packet_end = req.packet_end;
    unit_req.tag       = rpu_pkg::RayTagBits'(entry);
  end
  always_comb begin : route_request
    core_req_ready_o = '0;
    unit_req_valid_o = '0;
    unit_req_o       = '0;
    if (send) begin
      core_req_ready_o[core] = 1'b1;
      unit_req_valid_o[unit] = 1'b1;
    end
    for (int u = 0; u < Units; u++) unit_req_o[rpu_pkg::TuReqBits*u +: rpu_pkg::TuReqBits] = unit_req;
  end

  // ---------------------------------------------------------------------------------
  // Answers: each unit's as the core's stream {tag, pc, hit, t, u, v, prim, fault},
  // from the entry its tag names; per core, the next unit after the last one that
  // answered it.
  // ---------------------------------------------------------------------------------
  logic [Units*rpu_pkg::TraceRspBits-1:0] answer;
  logic [Units*TagBits-1:0]               answer_tag;  // the answer's request tag
  logic [Units*RayIdx-1:0]                answer_entry;
  rpu_pkg::tu_rsp_t                       a_rsp;
  rpu_pkg::trace_rsp_t                    a_out;
  always_comb begin : format_answers
    answer       = '0;
    answer_tag   = '0;
    answer_entry = '0;
    a_rsp        = '0;
    a_out        = '0;
    for (int u = 0; u < Units; u++) begin
      int unsigned e;
      a_rsp       = unit_rsp_i[rpu_pkg::TuRspBits*u +: rpu_pkg::TuRspBits];
      answer_entry[RayIdx*u +: RayIdx] = RayIdx'(a_rsp.tag);
      e           = u * UnitRays + (UnitRays > 1 ? 32'(RayIdx'(a_rsp.tag)) : 0);
      a_out       = '0;
      a_out.tag   = tag_q[TagBits*e +: TagBits];
      a_out.pc    = pc_q[32*e +: 32];
      answer_tag[TagBits*u +: TagBits] = a_out.tag;
      a_out.hit   = a_rsp.hit;
      a_out.t     = a_rsp.t;
      a_out.u     = a_rsp.u;
      a_out.v     = a_rsp.v;
      a_out.prim  = a_rsp.prim;
      a_out.fault = a_rsp.fault;
      answer[rpu_pkg::TraceRspBits*u +: rpu_pkg::TraceRspBits] = a_out;
    end
  end

  logic [Cores*UnitIdx-1:0] last_unit_d, last_unit_q;
  logic [Cores*UnitIdx-1:0] from;      // per core: the unit it takes an answer from
  logic [Cores-1:0]         found;
  logic [Units-1:0]         answered;  // the unit's answer is taken this cycle

  always_comb begin : pick_answer_unit
    found = '0;
    from  = '0;
    for (int c = 0; c < Cores; c++) begin
      for (int k = Units; k >= 1; k--) begin
        if (unit_rsp_valid_i[(32'(last_unit_q[UnitIdx*c +: UnitIdx]) + k) % Units]
            && 32'(answer_tag[TagBits*((32'(last_unit_q[UnitIdx*c +: UnitIdx]) + k) % Units) + CoreLsb +:
                              rpu_pkg::CoreBits]) == c) begin
          found[c]                    = 1'b1;
          from[UnitIdx*c +: UnitIdx]  = UnitIdx'((32'(last_unit_q[UnitIdx*c +: UnitIdx]) + k) % Units);
        end
      end
    end
  end

  always_comb begin : route_answers
    last_unit_d = last_unit_q;
    answered    = '0;
    core_rsp_o  = '0;
    for (int c = 0; c < Cores; c++) begin
      core_rsp_o[rpu_pkg::TraceRspBits*c +: rpu_pkg::TraceRspBits] =
          answer[rpu_pkg::TraceRspBits*from[UnitIdx*c +: UnitIdx] +: rpu_pkg::TraceRspBits];
      if (found[c] && core_rsp_ready_i[c]) begin
        answered[from[UnitIdx*c +: UnitIdx]] = 1'b1;
        last_unit_d[UnitIdx*c +: UnitIdx]    = from[UnitIdx*c +: UnitIdx];
      end
    end
  end
  assign core_rsp_valid_o = found;
  assign unit_rsp_ready_o = answered;

  always_comb begin : next_entries
    busy_d      = busy_q;
    tag_d       = tag_q;
    pc_d        = pc_q;
    last_core_d = last_core_q;
    for (int u = 0; u < Units; u++) begin
      if (answered[u]) busy_d[u*UnitRays + 32'(answer_entry[RayIdx*u +: RayIdx])] = 1'b0;
    end
    if (send) begin
      busy_d[32'(unit)*UnitRays + 32'(entry)]                 = 1'b1;
      tag_d[TagBits*(32'(unit)*UnitRays + 32'(entry)) +: TagBits] = req.tag;
      pc_d[32*(32'(unit)*UnitRays + 32'(entry)) +: 32]        = req.pc;
      last_core_d                                             = core;
    end
  end

  always_comb begin : next_locks
    locked_d    = locked_q;
    lock_unit_d = lock_unit_q;
    if (send) begin
      locked_d[core]                      = Packets != 0 && !req.packet_end;
      lock_unit_d[UnitIdx*core +: UnitIdx] = unit;
    end
  end

  always_ff @(posedge clk_i or negedge rst_ni) begin : regs
    if (!rst_ni) begin
      locked_q    <= '0;
      lock_unit_q <= '0;
      busy_q      <= '0;
      last_core_q <= '0;
      last_unit_q <= '0;
    end else begin
      locked_q    <= locked_d;
      lock_unit_q <= lock_unit_d;
      busy_q      <= busy_d;
      last_core_q <= last_core_d;
      last_unit_q <= last_unit_d;
    end
  end

  // An entry's tag and pc are read only while it is busy: no reset (thousands of bits with
  // packets on several units).
  always_ff @(posedge clk_i) begin : entry_regs
    tag_q <= tag_d;
    pc_q  <= pc_d;
  end

  assign idle_o = busy_q == '0;

  // A unit's work counters are the traversal statistics' business, not the shader's.
  // The answers' request tags are read for their core bits.
  logic unused;
  assign unused = ^{a_rsp.tag, a_rsp.nodes, a_rsp.leaves, a_rsp.tests, answer_tag};

`ifndef SYNTHESIS
  initial begin
    assert (UnitRays <= (1 << rpu_pkg::RayTagBits) && (UnitRays == 1 || (1 << RayIdx) == UnitRays))
      else $error("rpu_ray_dispatch: UnitRays %0d is not a power of two the ray tag holds", UnitRays);
  end
  always_ff @(posedge clk_i or negedge rst_ni) begin : check_answers
    if (rst_ni) begin
      for (int u = 0; u < Units; u++) begin
        assert (!unit_rsp_valid_i[u] || busy_q[u*UnitRays + 32'(answer_entry[RayIdx*u +: RayIdx])])
          else $error("rpu_ray_dispatch: unit %0d answers tag %0d, no ray in flight there", u,
                      answer_entry[RayIdx*u +: RayIdx]);
      end
    end
  end
`endif

endmodule
