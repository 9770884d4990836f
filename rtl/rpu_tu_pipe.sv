// A traversal unit whose Slots packets of rays share one node-step pipeline (docs/rtl.md,
// "The node-step pipeline"): bit for bit rpu_tu's results, counters and faults for every
// ray, with rpu_tu_slots' ports, so tu_cosim, the ray unit and the netlist testbench take
// either. A slot holds a packet of up to Packet rays that walk the tree together
// (docs/traversal.md "Packets"); Packet = 1 is one ray a slot.
//
//   set-up      Setups rpu_tu engines in HandOff mode round the ray into the format and
//               clip it to the scene box (§1-§2), one ray each at a time; a ray that
//               misses answers from its engine, any other moves to a slot.
//   forming     a set-up ray joins the packet being formed if it came in the same input
//               packet (the requests up to one with packet_end), has the same direction
//               signs and any-hit mode, and the packet has room; otherwise it opens a
//               packet in the lowest free slot, closing the one being formed. A packet
//               also closes when full, or when no ray of its input packet is left in
//               set-up. With Packet > 1 an arrivals table of the rays in set-up names
//               each one's input packet and tag, the engines seeing its entry as the tag.
//   slot        a packet's walk state: the node to visit, its stack (one RAM banked by
//               slot, an entry a node and per ray an interval and whether the ray pushed
//               it or deferred to it), which rays are active, waiting or done; and per
//               ray the ray, t_near, t_far, the nearest hit and the counters.
//   fetch       round robin among the slots with a node to visit: one node line a cycle
//               on the memory port, for every active ray of the packet. Every line asked
//               for holds an entry of a table of 2^LineTagBits lines in flight, named by
//               the request's tag, so answers may come in any order (rpu_top puts
//               rpu_inorder_port in front unless tu_by_tag).
//   node step   an inner node enters a pipeline of single-rounding ops, one a cycle, a
//               lane per ray of the packet: from_fp32 of the split | O < s, O == s,
//               s - O | (s - O) * inv | t_split <= t_far, <= 0, < t_near | decide: the
//               packet's next node, push, restart or fault. A leaf's end takes the same
//               compares on t_best (t_best <= t_far, and t_best < t_near of the entry a
//               pop would take) in a cycle no inner node enters, and pops in the decide
//               stage, again while the popped entry holds no ray that walks on.
//   leaf        a leaf's prim refs, then their intersection records, are fetched back
//               to back (LeafDepth records between the ref request and the IU at most),
//               a record's lines into one of Records buffers; each whole record (the
//               lowest buffer first) goes to the IU once per testing ray of its packet,
//               each test tagged with an entry of a table of Tests tests in flight, so
//               answers come in any order. An answer is folded into its ray's nearest
//               hit: a smaller t, or an equal t of a lower list index. That equals the
//               sequential walk's result: the IU hits only in (t_min, t_best) and a
//               test leaves with its ray's t_best of the time, at least the sequential
//               walk's, so the hits it reports include the sequential walk's and its
//               nearest, lowest-index hit is the same. An any-hit packet keeps one
//               record's tests in flight, so each ray stops at the same test.
//   restart     a packet whose stack would overflow walks its rays again one by one,
//               each from the root with its set-up interval (solo): a ray alone faults
//               where its own walk does. A packet of one ray is solo from the start.
//   finish      round robin among the finished slots, then the packet's rays one a
//               cycle: t, u, v widened to fp32, t back to world space, the response;
//               the slot is free when its last ray's is taken.
module rpu_tu_pipe #(
  parameter int unsigned ExpBits    = rpu_pkg::FormatFp32ExponentBits,
  parameter int unsigned FracBits   = rpu_pkg::FormatFp32FractionBits,
  parameter int unsigned IsectMode  = rpu_pkg::IsectModeWoop,
  parameter int unsigned StackDepth = rpu_pkg::ConfigDefaultStackDepth,
  parameter int unsigned Slots      = 16,
  parameter int unsigned Packet     = 1,  // rays a slot walks together
  parameter int unsigned Setups     = 2,
  parameter int unsigned LeafDepth  = 16,
  parameter int unsigned Tests      = 32,
  parameter int unsigned LineTagBits = 4,  // lines in flight on the memory port: 2^LineTagBits
  parameter int unsigned Records     = 4   // intersection records being read at once
) (
  input  logic              clk_i,
  input  logic              rst_ni,

  input  rpu_pkg::tu_cfg_t  cfg_i,

  input  logic              req_valid_i,
  output logic              req_ready_o,
  input  rpu_pkg::tu_req_t  req_i,

  output logic              rsp_valid_o,
  input  logic              rsp_ready_i,
  output rpu_pkg::tu_rsp_t  rsp_o,

  output logic              mem_req_valid_o,
  input  logic              mem_req_ready_i,
  output rpu_pkg::mem_req_t mem_req_o,

  input  logic              mem_rsp_valid_i,
  output logic              mem_rsp_ready_o,
  input  rpu_pkg::mem_rsp_t mem_rsp_i,

  output logic              iu_req_valid_o,
  input  logic              iu_req_ready_i,
  output rpu_pkg::iu_req_t  iu_req_o,

  input  logic              iu_rsp_valid_i,
  output logic              iu_rsp_ready_o,
  input  rpu_pkg::iu_rsp_t  iu_rsp_i
);

  localparam int unsigned W = 1 + ExpBits + FracBits;
  localparam logic [W-1:0] Zero = '0;
  localparam int unsigned SlotBits = $clog2(Slots);
  localparam int unsigned P = Packet;
  localparam int unsigned LaneBits = Packet > 1 ? $clog2(Packet) : 1;  // a ray's place in its packet
  localparam int unsigned Lanes = Slots * Packet;
  localparam int unsigned IndexBits = rpu_pkg::KdNodeIndexBits;
  // A stack entry: {node, pushed by, deferred to, per ray {t_near, t_far}}.
  localparam int unsigned EntryBits = IndexBits + 2 * Packet + 2 * W * Packet;
  localparam int unsigned SpBits = $clog2(StackDepth + 1);
  localparam int unsigned DepthBits = $clog2(StackDepth);
  localparam int unsigned TestBits = $clog2(Tests);
  localparam int unsigned PendingBits = $clog2(LeafDepth * Packet + Tests + 1);
  localparam int unsigned WorkBits = $clog2(LeafDepth + 1);
  localparam int unsigned RecordBytes = IsectMode == rpu_pkg::IsectModeWatertight
                                        ? rpu_pkg::TriangleRecordWatertightBytes
                                        : rpu_pkg::TriangleRecordWoopBytes;
  localparam int unsigned RecordLines = RecordBytes / rpu_pkg::MemLineBytes;
  localparam int unsigned LineBits = 8 * rpu_pkg::MemLineBytes;
  localparam int unsigned OffsetBits = $clog2(rpu_pkg::MemLineBytes);
  localparam int unsigned WordSelBits = OffsetBits - 2;
  localparam int unsigned GotBits = $clog2(RecordLines + 1);
  localparam int unsigned SetupBits = $clog2(Setups + 1);
  // A set-up engine's start port, flat: {dir_le0, any_hit, t_far, t_near, inv, ray}.
  localparam int unsigned StartBits = rpu_pkg::IuReqBits + 5 * 32 + 1 + 3;
  localparam int unsigned LineSelBits = $clog2(RecordLines);
  localparam int unsigned BufBits = $clog2(Records);
  // Memory requests in flight, each an entry of the line table, its index the tag:
  // {kind, slot, the node's or ref's word, the ref's list index, record buffer, line}.
  localparam int unsigned Lines = 1 << LineTagBits;
  localparam logic [1:0] KindNode = 2'd0, KindRef = 2'd1, KindRecord = 2'd2;
  localparam int unsigned AskBits = 2 + SlotBits + WordSelBits + IndexBits + BufBits + LineSelBits;
  localparam int unsigned JobBits = SlotBits + IndexBits + 32;  // {slot, list index, prim}
  localparam int unsigned TestJobBits = LaneBits + JobBits;    // {ray, slot, list index, prim}
  localparam int unsigned JobIndexBits = $clog2(LeafDepth);
  // A slot's jobs in flight have list indices within LeafDepth of each other: their low
  // OrdBits bits tell them apart.
  localparam int unsigned OrdBits = $clog2(LeafDepth) + 1;
  // With Packet > 1, the rays in set-up (an engine holds up to three: its own, its
  // output register and its skid buffer) and the input packets they may belong to.
  localparam int unsigned Arrivals = 4 * Setups;
  localparam int unsigned ArrBits = $clog2(Arrivals);
  localparam int unsigned SeqBits = ArrBits + 1;

  typedef enum logic [3:0] {
    PhFree,     // no packet
    PhForm,     // rays joining
    PhReady,    // a node to fetch
    PhNode,     // its line on the way, or the node step in the pipeline
    PhLeaf,     // a leaf's tests on the way
    PhLeafEnd,  // the leaf's tests answered (or a pop found no ray): waiting for the pipeline
    PhPop,      // the leaf's end in the pipeline
    PhDone,     // waiting for the finish stage
    PhFinish    // in the finish stage
  } phase_e;

  // The nearest-hit fold's compares on format values that are not NaN (an IU hit's t
  // lies in (t_min, t_best)): exact, so no FP unit is needed.
  function automatic logic fp_lt(input logic [W-1:0] a, input logic [W-1:0] b);
    fp_lt = !(a[W-2:0] == '0 && b[W-2:0] == '0)
            && (a[W-1] != b[W-1] ? a[W-1] : a[W-1] ? a[W-2:0] > b[W-2:0] : a[W-2:0] < b[W-2:0]);
  endfunction
  function automatic logic fp_eq(input logic [W-1:0] a, input logic [W-1:0] b);
    fp_eq = a == b || (a[W-2:0] == '0 && b[W-2:0] == '0);
  endfunction
  // The lowest ray of `rays` from ray `from` on (0 if none), and whether there is one.
  function automatic logic [LaneBits-1:0] ray_from(input logic [P-1:0] rays, input int unsigned from);
    ray_from = '0;
    for (int r = P - 1; r >= 0; r--) begin
      if (rays[r] && 32'(r) >= from) ray_from = LaneBits'(r);
    end
  endfunction
  function automatic logic any_ray_from(input logic [P-1:0] rays, input int unsigned from);
    any_ray_from = 1'b0;
    for (int r = 0; r < P; r++) begin
      if (rays[r] && 32'(r) >= from) any_ray_from = 1'b1;
    end
  endfunction
  // The flat index of ray r of slot s.
  function automatic int unsigned ray_at(input logic [SlotBits-1:0] s, input logic [LaneBits-1:0] r);
    ray_at = 32'(s) * P + (P > 1 ? 32'(r) : 0);
  endfunction

  // --- The packets' state (per slot) and the rays' (per slot and lane), one flat
  // vector per field (Yosys 0.23). ---
  logic [Slots*4-1:0]         phase_all;
  logic [Slots-1:0]           any_hit_all, solo_all;
  logic [Slots*P-1:0]         valid_all, active_all, waiting_all, testing_all;
  logic [Slots*3-1:0]         signs_all;
  logic [Slots*LaneBits-1:0]  solo_lane_all;
  logic [Slots*32-1:0]        first_all;
  logic [Slots*IndexBits-1:0] node_all, count_all, k_all;
  logic [Slots*SpBits-1:0]    sp_all;
  logic [Slots*PendingBits-1:0] pending_all;

  logic [Lanes*rpu_pkg::RayTagBits-1:0] tag_all;
  logic [Lanes-1:0]           hit_all, fault_all;
  logic [Lanes*3*W-1:0]       origin_all, dir_all, inv_all;
  logic [Lanes*3-1:0]         dir_le0_all;
  logic [Lanes*6-1:0]         axes_all;  // {kz, ky, kx}
  logic [Lanes*W-1:0]         t_min_all, near_all, far_all, best_all, u_all, v_all, shear_x_all, shear_y_all;
  logic [Lanes*32-1:0]        hit_prim_all, nodes_all, leaves_all, tests_all;
  logic [Lanes*IndexBits-1:0] best_k_all;

  function automatic logic [W-1:0] pick_w(input logic [Lanes*W-1:0] all, input int unsigned ray);
    pick_w = all[ray*W +: W];
  endfunction
  function automatic logic [W-1:0] pick_axis(input logic [Lanes*3*W-1:0] all, input int unsigned ray,
                                             input logic [1:0] a);
    pick_axis = all[(ray*3 + 32'(a))*W +: W];
  endfunction

  // --- Set-up: Setups rpu_tu engines in HandOff mode. ---
  logic [Setups-1:0]                   setup_req_valid, setup_req_ready, setup_rsp_valid, setup_rsp_ready;
  logic [Setups-1:0]                   start_valid, start_ready;
  logic [Setups*rpu_pkg::TuRspBits-1:0] setup_rsp, setup_out;
  logic [Setups*StartBits-1:0]         start;
  logic [Setups-1:0]                   unused_setup_ports;
  rpu_pkg::tu_req_t                    engine_req;

  for (genvar i = 0; i < Setups; i++) begin : g_setup
    rpu_pkg::tu_rsp_t  engine_rsp;
    rpu_pkg::iu_req_t  engine_ray, engine_test;
    rpu_pkg::mem_req_t engine_mem_req;
    logic              engine_mem_valid, engine_mem_ready, engine_iu_valid, engine_iu_ready;
    logic [3*32-1:0]   engine_inv;
    logic [31:0]       engine_near, engine_far;
    logic              engine_any_hit;
    logic [2:0]        engine_dir_le0;
    rpu_tu #(.ExpBits(ExpBits), .FracBits(FracBits), .IsectMode(IsectMode), .StackDepth(StackDepth),
             .HandOff(1'b1)) u_engine (
      .clk_i, .rst_ni, .cfg_i,
      .req_valid_i(setup_req_valid[i]), .req_ready_o(setup_req_ready[i]), .req_i(engine_req),
      .rsp_valid_o(setup_rsp_valid[i]), .rsp_ready_i(setup_rsp_ready[i]), .rsp_o(engine_rsp),
      .mem_req_valid_o(engine_mem_valid), .mem_req_ready_i(1'b0), .mem_req_o(engine_mem_req),
      .mem_rsp_valid_i(1'b0), .mem_rsp_ready_o(engine_mem_ready), .mem_rsp_i('0),
      .iu_req_valid_o(engine_iu_valid), .iu_req_ready_i(1'b0), .iu_req_o(engine_test),
      .iu_rsp_valid_i(1'b0), .iu_rsp_ready_o(engine_iu_ready), .iu_rsp_i('0),
      .start_valid_o(start_valid[i]), .start_ready_i(start_ready[i]), .start_ray_o(engine_ray),
      .start_inv_o(engine_inv), .start_t_near_o(engine_near), .start_t_far_o(engine_far),
      .start_any_hit_o(engine_any_hit), .start_dir_le0_o(engine_dir_le0)
    );
    assign setup_rsp[i*rpu_pkg::TuRspBits +: rpu_pkg::TuRspBits] = engine_rsp;
    assign start[i*StartBits +: StartBits] = {engine_dir_le0, engine_any_hit, engine_far, engine_near,
                                              engine_inv, engine_ray};
    // A HandOff engine never walks: its memory and IU ports stay idle.
    assign unused_setup_ports[i] = ^{engine_mem_valid, engine_mem_req, engine_mem_ready, engine_iu_valid,
                                     engine_test, engine_iu_ready};
  end

  // Rays in: the lowest engine whose buffer has room.
  logic [SetupBits-1:0] setup_free;
  logic                 arrival_room;
  always_comb begin : pick_free_setup
    setup_free = SetupBits'(Setups);
    for (int i = Setups - 1; i >= 0; i--) begin
      if (setup_req_ready[i]) setup_free = SetupBits'(i);
    end
  end
  for (genvar i = 0; i < Setups; i++) begin : g_setup_req
    assign setup_req_valid[i] = req_valid_i && arrival_room && setup_free == SetupBits'(i);
  end
  assign req_ready_o = |setup_req_ready && arrival_room;

  // Set-up rays to their packets' slots.
  logic                 give, give_any_free, start_arb_valid, joins, open, form_full, form_ends;
  logic [SlotBits-1:0]  give_slot, free_slot;
  logic [LaneBits-1:0]  give_lane;
  logic [StartBits-1:0] given;
  logic [$clog2(Setups > 1 ? Setups : 2)-1:0] start_index;
  logic [rpu_pkg::RayTagBits-1:0] given_tag;  // the ray's own tag
  logic [SeqBits-1:0]   given_seq;            // its input packet
  logic [2:0]           given_signs;
  always_comb begin : pick_free_slot
    free_slot     = '0;
    give_any_free = 1'b0;
    for (int i = Slots - 1; i >= 0; i--) begin
      if (phase_all[i*4 +: 4] == PhFree) begin
        free_slot     = SlotBits'(i);
        give_any_free = 1'b1;
      end
    end
  end
  rpu_rr_arbiter #(.Inputs(Setups), .Width(StartBits)) u_start_arb (
    .clk_i, .rst_ni,
    .valid_i(start_valid), .ready_o(start_ready), .data_i(start),
    .valid_o(start_arb_valid), .ready_i(joins || give_any_free), .data_o(given), .index_o(start_index)
  );
  assign give = start_arb_valid && (joins || give_any_free);

  rpu_pkg::iu_req_t given_ray;
  logic [3*32-1:0]  given_inv;
  logic [31:0]      given_near, given_far;
  logic             given_any_hit;
  logic [2:0]       given_dir_le0;
  assign {given_dir_le0, given_any_hit, given_far, given_near, given_inv, given_ray} = given;
  for (genvar a = 0; a < 3; a++) begin : g_sign
    assign given_signs[a] = given_inv[a*32 + W - 1];
  end

  // The packet being formed.
  logic                form_open_d, form_open_q, form_any_hit_d, form_any_hit_q;
  logic [SlotBits-1:0] form_slot_d, form_slot_q;
  logic [LaneBits:0]   form_rays_d, form_rays_q;
  logic [SeqBits-1:0]  form_seq_d, form_seq_q;
  logic [2:0]          form_signs_d, form_signs_q;
  assign joins = P > 1 && start_arb_valid && form_open_q && given_seq == form_seq_q && given_signs == form_signs_q
                && given_any_hit == form_any_hit_q && form_rays_q != (LaneBits + 1)'(P);
  assign open         = give && !joins;
  assign give_slot    = joins ? form_slot_q : free_slot;
  assign give_lane    = joins ? LaneBits'(form_rays_q) : '0;
  assign form_full    = (joins ? form_rays_q + (LaneBits + 1)'(1) : (LaneBits + 1)'(1)) == (LaneBits + 1)'(P);
  assign form_open_d  = give ? !form_full : form_open_q && !form_ends;
  assign form_slot_d  = give ? give_slot : form_slot_q;
  assign form_rays_d  = give ? (joins ? form_rays_q : '0) + (LaneBits + 1)'(1) : form_rays_q;
  assign form_seq_d   = give ? given_seq : form_seq_q;
  assign form_signs_d = give ? given_signs : form_signs_q;
  assign form_any_hit_d = give ? given_any_hit : form_any_hit_q;

  // The packets closed in this cycle: the one being formed when another opens or its
  // input packet has no ray left in set-up, and the one a ray fills.
  logic close_formed, close_given;
  assign close_formed = form_open_q && (open || form_ends);
  assign close_given  = give && form_full;

  // The struct fields the arrivals table reads, at module scope (Yosys 0.23 takes no
  // member access inside a generate block).
  logic [rpu_pkg::RayTagBits-1:0] in_tag, given_entry_tag;
  logic                           in_end;
  logic [ArrBits-1:0]             entry_free;
  logic [Setups*ArrBits-1:0]      setup_rsp_entry;  // the entry each engine answers for
  assign in_tag         = req_i.tag;
  assign in_end         = req_i.packet_end;
  assign given_entry_tag = given_ray.tag;
  always_comb begin : engine_request
    engine_req = req_i;
    if (P > 1) engine_req.tag = rpu_pkg::RayTagBits'(entry_free);
  end
  for (genvar i = 0; i < Setups; i++) begin : g_setup_entry
    assign setup_rsp_entry[i*ArrBits +: ArrBits] =
        setup_rsp[i*rpu_pkg::TuRspBits + rpu_pkg::TuRspBits - rpu_pkg::RayTagBits +: ArrBits];
  end

  if (P > 1) begin : g_arrivals
    // The rays in set-up: an entry per ray, its index the engines' tag.
    logic [Arrivals-1:0]                     busy_d, busy_q, freed;
    logic [Arrivals*rpu_pkg::RayTagBits-1:0] tags_d, tags_q;
    logic [Arrivals*SeqBits-1:0]             seqs_d, seqs_q;
    logic [SeqBits-1:0]                      in_seq_d, in_seq_q;  // the input packet taking rays
    logic [ArrBits-1:0]                      given_entry;
    logic                                    accept, formed_left;
    always_comb begin : pick_free_arrival
      entry_free   = '0;
      arrival_room = 1'b0;
      for (int e = Arrivals - 1; e >= 0; e--) begin
        if (!busy_q[e]) begin
          entry_free   = ArrBits'(e);
          arrival_room = 1'b1;
        end
      end
    end
    assign accept      = req_valid_i && req_ready_o;
    assign in_seq_d    = in_seq_q + SeqBits'(accept && in_end);
    assign given_entry = given_entry_tag[ArrBits-1:0];
    logic unused_entry_high;  // the engines' tags name an entry
    assign unused_entry_high = ^given_entry_tag[rpu_pkg::RayTagBits-1:ArrBits];
    assign given_tag   = tags_q[32'(given_entry)*rpu_pkg::RayTagBits +: rpu_pkg::RayTagBits];
    assign given_seq   = seqs_q[32'(given_entry)*SeqBits +: SeqBits];

    // A ray leaves set-up when its slot takes it or its miss is answered (the answer
    // leaves with the ray's own tag).
    always_comb begin : leave_setup
      freed     = '0;
      setup_out = setup_rsp;
      if (give) freed[given_entry] = 1'b1;
      for (int i = 0; i < Setups; i++) begin
        setup_out[i*rpu_pkg::TuRspBits + rpu_pkg::TuRspBits - rpu_pkg::RayTagBits +: rpu_pkg::RayTagBits] =
            tags_q[32'(setup_rsp_entry[i*ArrBits +: ArrBits])*rpu_pkg::RayTagBits +: rpu_pkg::RayTagBits];
        if (setup_rsp_valid[i] && setup_rsp_ready[i]) freed[setup_rsp_entry[i*ArrBits +: ArrBits]] = 1'b1;
      end
    end
    always_comb begin : formed_rays_left
      formed_left = 1'b0;
      for (int e = 0; e < Arrivals; e++) begin
        if (busy_q[e] && seqs_q[e*SeqBits +: SeqBits] == form_seq_q) formed_left = 1'b1;
      end
    end
    assign form_ends = !formed_left && in_seq_q != form_seq_q;
    for (genvar e = 0; e < Arrivals; e++) begin : g_arrival
      logic alloc;
      assign alloc = accept && entry_free == ArrBits'(e);
      assign busy_d[e] = alloc || (busy_q[e] && !freed[e]);
      assign tags_d[e*rpu_pkg::RayTagBits +: rpu_pkg::RayTagBits] =
          alloc ? in_tag : tags_q[e*rpu_pkg::RayTagBits +: rpu_pkg::RayTagBits];
      assign seqs_d[e*SeqBits +: SeqBits] = alloc ? in_seq_q : seqs_q[e*SeqBits +: SeqBits];
    end
    always_ff @(posedge clk_i or negedge rst_ni) begin : arrival_regs
      if (!rst_ni) begin
        busy_q   <= '0;
        tags_q   <= '0;
        seqs_q   <= '0;
        in_seq_q <= '0;
      end else begin
        busy_q   <= busy_d;
        tags_q   <= tags_d;
        seqs_q   <= seqs_d;
        in_seq_q <= in_seq_d;
      end
    end
  end else begin : g_alone
    // A packet of one ray closes as it opens: the engines see the ray's own tag.
    assign arrival_room = 1'b1;
    assign entry_free   = '0;
    assign given_tag    = given_entry_tag;
    assign given_seq    = '0;
    assign setup_out    = setup_rsp;
    assign form_ends    = 1'b0;
    logic unused_alone;
    assign unused_alone = ^{in_tag, in_end, given_signs, setup_rsp_entry};
  end

  // --- Events: each names its slot (and ray); at most one of a kind per cycle. ---
  logic                 fetch, leaf_in, inner_in, pop_enter, ref_issue, test_issue, test_last, answer;
  logic                 fin_take, fin_done, decide;
  logic [SlotBits-1:0]  fetch_slot, line_slot, pop_slot, ref_slot, test_slot, answer_slot;
  logic [SlotBits-1:0]  fin_take_slot, fin_slot_q, decide_slot;
  logic [LaneBits-1:0]  test_lane, answer_lane;
  logic [IndexBits-1:0] leaf_count, answer_k, decide_node;
  logic [31:0]          leaf_first, answer_prim;
  logic                 answer_wins;
  logic                 decide_push, decide_pop, decide_solo;
  logic [LaneBits-1:0]  decide_solo_lane;
  logic [P-1:0]         decide_active, decide_waiting;
  logic [P-1:0]         decide_near_we, decide_far_we, decide_fault, decide_reset;
  logic [P*W-1:0]       decide_near, decide_far;
  phase_e               decide_phase;
  logic [$clog2(P + 1)-1:0] ref_tests;  // the tests a ref's record owes: its packet's testing rays

  // --- Packets. ---
  for (genvar i = 0; i < Slots; i++) begin : g_slot
    localparam logic [SlotBits-1:0] Me = SlotBits'(i);
    phase_e                phase_d, phase_q;
    logic                  any_hit_d, any_hit_q, solo_d, solo_q;
    logic [P-1:0]          valid_d, valid_q, active_d, active_q, waiting_d, waiting_q, lane_hit;
    logic [2:0]            signs_d, signs_q;
    logic [LaneBits-1:0]   solo_lane_d, solo_lane_q, lowest;
    logic [31:0]           first_d, first_q;
    logic [IndexBits-1:0]  node_d, node_q, count_d, count_q, k_d, k_q;
    logic [SpBits-1:0]     sp_d, sp_q;
    logic [PendingBits-1:0] pending_d, pending_q;
    logic                  testing_any, leaf_over, close;

    assign lane_hit    = hit_all[i*P +: P];
    assign testing_any = |testing_all[i*P +: P];
    // A leaf is over when its tests are answered: all of them, or every any-hit ray's
    // first hit.
    assign leaf_over = phase_q == PhLeaf && pending_q == '0 && (k_q == count_q || !testing_any);
    assign close     = (close_formed && form_slot_q == Me) || (close_given && give_slot == Me);
    assign lowest    = ray_from(valid_d, 0);

    always_comb begin : next_packet
      phase_d     = phase_q;
      any_hit_d   = any_hit_q;
      solo_d      = solo_q;
      valid_d     = valid_q;
      active_d    = active_q;
      waiting_d   = waiting_q;
      signs_d     = signs_q;
      solo_lane_d = solo_lane_q;
      first_d     = first_q;
      node_d      = node_q;
      count_d     = count_q;
      k_d         = k_q;
      sp_d        = sp_q;
      pending_d   = pending_q + (ref_issue && ref_slot == Me ? PendingBits'(ref_tests) : '0)
                              - PendingBits'(answer && answer_slot == Me);

      if (give && give_slot == Me) begin
        if (open) begin
          phase_d   = PhForm;
          any_hit_d = given_any_hit;
          signs_d   = given_signs;
          valid_d   = '0;
          node_d    = '0;
          sp_d      = '0;
        end
        valid_d[give_lane] = 1'b1;
      end
      if (close) begin
        phase_d     = PhReady;
        active_d    = valid_d;
        waiting_d   = '0;
        solo_d      = (valid_d & (valid_d - P'(1))) == '0;  // one ray
        solo_lane_d = lowest;
      end
      if (fetch && fetch_slot == Me) phase_d = PhNode;
      if (leaf_in && line_slot == Me) begin
        phase_d = PhLeaf;
        first_d = leaf_first;
        count_d = leaf_count;
        k_d     = '0;
      end
      if (decide && decide_slot == Me) begin
        phase_d     = decide_phase;
        node_d      = decide_node;
        active_d    = decide_active;
        waiting_d   = decide_waiting;
        solo_d      = decide_solo;
        solo_lane_d = decide_solo_lane;
        if (decide_push) sp_d = sp_q + SpBits'(1);
        if (decide_pop) sp_d = sp_q - SpBits'(1);
        if (decide_reset != '0) sp_d = '0;
      end
      if (ref_issue && ref_slot == Me) k_d = k_q + IndexBits'(1);
      if (leaf_over) phase_d = PhLeafEnd;
      if (pop_enter && pop_slot == Me) phase_d = PhPop;
      if (fin_take && fin_take_slot == Me) phase_d = PhFinish;
      if (fin_done && fin_slot_q == Me) phase_d = PhFree;
    end

    always_ff @(posedge clk_i or negedge rst_ni) begin : packet_regs
      if (!rst_ni) begin
        phase_q     <= PhFree;
        any_hit_q   <= 1'b0;
        solo_q      <= 1'b0;
        valid_q     <= '0;
        active_q    <= '0;
        waiting_q   <= '0;
        signs_q     <= '0;
        solo_lane_q <= '0;
        first_q     <= '0;
        node_q      <= '0;
        count_q     <= '0;
        k_q         <= '0;
        sp_q        <= '0;
        pending_q   <= '0;
      end else begin
        phase_q     <= phase_d;
        any_hit_q   <= any_hit_d;
        solo_q      <= solo_d;
        valid_q     <= valid_d;
        active_q    <= active_d;
        waiting_q   <= waiting_d;
        signs_q     <= signs_d;
        solo_lane_q <= solo_lane_d;
        first_q     <= first_d;
        node_q      <= node_d;
        count_q     <= count_d;
        k_q         <= k_d;
        sp_q        <= sp_d;
        pending_q   <= pending_d;
      end
    end

    assign phase_all[i*4 +: 4]                       = phase_q;
    assign any_hit_all[i]                            = any_hit_q;
    assign solo_all[i]                               = solo_q;
    assign valid_all[i*P +: P]                       = valid_q;
    assign active_all[i*P +: P]                      = active_q;
    assign waiting_all[i*P +: P]                     = waiting_q;
    // The rays that test a leaf's records: the active ones, but any-hit rays that hit.
    assign testing_all[i*P +: P]                     = active_q & ~(any_hit_q ? lane_hit : '0);
    assign signs_all[i*3 +: 3]                       = signs_q;
    assign solo_lane_all[i*LaneBits +: LaneBits]     = solo_lane_q;
    assign first_all[i*32 +: 32]                     = first_q;
    assign node_all[i*IndexBits +: IndexBits]        = node_q;
    assign count_all[i*IndexBits +: IndexBits]       = count_q;
    assign k_all[i*IndexBits +: IndexBits]           = k_q;
    assign sp_all[i*SpBits +: SpBits]                = sp_q;
    assign pending_all[i*PendingBits +: PendingBits] = pending_q;
  end

  // --- Rays. ---
  logic [P-1:0] fetch_active, leaf_active;
  assign fetch_active = active_all[32'(fetch_slot)*P +: P];
  assign leaf_active  = active_all[32'(line_slot)*P +: P];
  for (genvar j = 0; j < Lanes; j++) begin : g_ray
    localparam logic [SlotBits-1:0] MySlot = SlotBits'(j / P);
    localparam int unsigned         MyLane = j % P;
    logic [rpu_pkg::RayTagBits-1:0] tag_d, tag_q;
    logic                  hit_d, hit_q, fault_d, fault_q;
    logic [3*W-1:0]        origin_d, origin_q, dir_d, dir_q, inv_d, inv_q;
    logic [2:0]            dir_le0_d, dir_le0_q;
    logic [5:0]            axes_d, axes_q;
    logic [W-1:0]          t_min_d, t_min_q, near_d, near_q, far_d, far_q, best_d, best_q;
    logic [W-1:0]          near0_d, near0_q, far0_d, far0_q, t_max_d, t_max_q;  // for a restart
    logic [W-1:0]          u_d, u_q, v_d, v_q, shear_x_d, shear_x_q, shear_y_d, shear_y_q;
    logic [31:0]           hit_prim_d, hit_prim_q;
    logic [31:0]           nodes_d, nodes_q, leaves_d, leaves_q, tests_d, tests_q;
    logic [IndexBits-1:0]  best_k_d, best_k_q;
    logic                  given_here, decided_here;

    assign given_here   = give && give_slot == MySlot && 32'(give_lane) == MyLane;
    assign decided_here = decide && decide_slot == MySlot;

    always_comb begin : next_ray
      tag_d      = tag_q;
      hit_d      = hit_q;
      fault_d    = fault_q;
      origin_d   = origin_q;
      dir_d      = dir_q;
      inv_d      = inv_q;
      dir_le0_d  = dir_le0_q;
      axes_d     = axes_q;
      t_min_d    = t_min_q;
      near_d     = near_q;
      far_d      = far_q;
      best_d     = best_q;
      near0_d    = near0_q;
      far0_d     = far0_q;
      t_max_d    = t_max_q;
      u_d        = u_q;
      v_d        = v_q;
      shear_x_d  = shear_x_q;
      shear_y_d  = shear_y_q;
      hit_prim_d = hit_prim_q;
      nodes_d    = nodes_q;
      leaves_d   = leaves_q;
      tests_d    = tests_q;
      best_k_d   = best_k_q;

      if (given_here) begin
        tag_d     = given_tag;
        hit_d     = 1'b0;
        fault_d   = 1'b0;
        for (int a = 0; a < 3; a++) begin
          origin_d[a*W +: W] = given_ray.origin[a*32 +: W];
          dir_d[a*W +: W]    = given_ray.direction[a*32 +: W];
          inv_d[a*W +: W]    = given_inv[a*32 +: W];
        end
        dir_le0_d = given_dir_le0;
        axes_d    = {given_ray.kz, given_ray.ky, given_ray.kx};
        t_min_d   = given_ray.t_min[W-1:0];
        near_d    = given_near[W-1:0];
        far_d     = given_far[W-1:0];
        best_d    = given_ray.t_best[W-1:0];
        near0_d   = given_near[W-1:0];
        far0_d    = given_far[W-1:0];
        t_max_d   = given_ray.t_best[W-1:0];
        shear_x_d = given_ray.shear_x[W-1:0];
        shear_y_d = given_ray.shear_y[W-1:0];
        nodes_d   = '0;
        leaves_d  = '0;
        tests_d   = '0;
      end
      if (fetch && fetch_slot == MySlot && fetch_active[MyLane]) nodes_d = nodes_q + 32'd1;
      if (leaf_in && line_slot == MySlot && leaf_active[MyLane]) leaves_d = leaves_q + 32'd1;
      if (decided_here) begin
        fault_d = fault_q || decide_fault[MyLane];
        if (decide_near_we[MyLane]) near_d = decide_near[MyLane*W +: W];
        if (decide_far_we[MyLane]) far_d = decide_far[MyLane*W +: W];
        if (decide_reset[MyLane]) begin
          // Walked again alone, from its set-up.
          hit_d    = 1'b0;
          fault_d  = 1'b0;
          near_d   = near0_q;
          far_d    = far0_q;
          best_d   = t_max_q;
          nodes_d  = '0;
          leaves_d = '0;
          tests_d  = '0;
        end
      end
      if (test_issue && test_slot == MySlot && 32'(test_lane) == MyLane) tests_d = tests_q + 32'd1;
      if (answer && answer_slot == MySlot && 32'(answer_lane) == MyLane && answer_wins) begin
        hit_d      = 1'b1;
        best_d     = iu_rsp_i.t[W-1:0];
        u_d        = iu_rsp_i.u[W-1:0];
        v_d        = iu_rsp_i.v[W-1:0];
        hit_prim_d = answer_prim;
        best_k_d   = answer_k;
      end
    end

    always_ff @(posedge clk_i or negedge rst_ni) begin : ray_regs
      if (!rst_ni) begin
        tag_q      <= '0;
        hit_q      <= 1'b0;
        fault_q    <= 1'b0;
        origin_q   <= '0;
        dir_q      <= '0;
        inv_q      <= '0;
        dir_le0_q  <= '0;
        axes_q     <= '0;
        t_min_q    <= '0;
        near_q     <= '0;
        far_q      <= '0;
        best_q     <= '0;
        near0_q    <= '0;
        far0_q     <= '0;
        t_max_q    <= '0;
        u_q        <= '0;
        v_q        <= '0;
        shear_x_q  <= '0;
        shear_y_q  <= '0;
        hit_prim_q <= '0;
        nodes_q    <= '0;
        leaves_q   <= '0;
        tests_q    <= '0;
        best_k_q   <= '0;
      end else begin
        tag_q      <= tag_d;
        hit_q      <= hit_d;
        fault_q    <= fault_d;
        origin_q   <= origin_d;
        dir_q      <= dir_d;
        inv_q      <= inv_d;
        dir_le0_q  <= dir_le0_d;
        axes_q     <= axes_d;
        t_min_q    <= t_min_d;
        near_q     <= near_d;
        far_q      <= far_d;
        best_q     <= best_d;
        near0_q    <= near0_d;
        far0_q     <= far0_d;
        t_max_q    <= t_max_d;
        u_q        <= u_d;
        v_q        <= v_d;
        shear_x_q  <= shear_x_d;
        shear_y_q  <= shear_y_d;
        hit_prim_q <= hit_prim_d;
        nodes_q    <= nodes_d;
        leaves_q   <= leaves_d;
        tests_q    <= tests_d;
        best_k_q   <= best_k_d;
      end
    end

    assign tag_all[j*rpu_pkg::RayTagBits +: rpu_pkg::RayTagBits] = tag_q;
    assign hit_all[j]                                            = hit_q;
    assign fault_all[j]                                          = fault_q;
    assign origin_all[j*3*W +: 3*W]                              = origin_q;
    assign dir_all[j*3*W +: 3*W]                                 = dir_q;
    assign inv_all[j*3*W +: 3*W]                                 = inv_q;
    assign dir_le0_all[j*3 +: 3]                                 = dir_le0_q;
    assign axes_all[j*6 +: 6]                                    = axes_q;
    assign t_min_all[j*W +: W]                                   = t_min_q;
    assign near_all[j*W +: W]                                    = near_q;
    assign far_all[j*W +: W]                                     = far_q;
    assign best_all[j*W +: W]                                    = best_q;
    assign u_all[j*W +: W]                                       = u_q;
    assign v_all[j*W +: W]                                       = v_q;
    assign shear_x_all[j*W +: W]                                 = shear_x_q;
    assign shear_y_all[j*W +: W]                                 = shear_y_q;
    assign hit_prim_all[j*32 +: 32]                              = hit_prim_q;
    assign nodes_all[j*32 +: 32]                                 = nodes_q;
    assign leaves_all[j*32 +: 32]                                = leaves_q;
    assign tests_all[j*32 +: 32]                                 = tests_q;
    assign best_k_all[j*IndexBits +: IndexBits]                  = best_k_q;
  end

  // Slot masks for the round-robin picks.
  logic [Slots-1:0] ready_mask, leaf_end_mask, done_mask, ref_mask;
  for (genvar i = 0; i < Slots; i++) begin : g_mask
    logic [3:0] phase;
    assign phase = phase_all[i*4 +: 4];
    assign ready_mask[i]    = phase == PhReady;
    assign leaf_end_mask[i] = phase == PhLeafEnd;
    assign done_mask[i]     = phase == PhDone;
    // A ref to fetch: any left in the list; an any-hit packet one at a time, while a
    // ray of it tests.
    assign ref_mask[i] = phase == PhLeaf
                         && k_all[i*IndexBits +: IndexBits] != count_all[i*IndexBits +: IndexBits]
                         && (!any_hit_all[i] || (pending_all[i*PendingBits +: PendingBits] == '0
                                                 && testing_all[i*P +: P] != '0));
  end

  // --- Memory: record lines first, then refs, then nodes; answers by tag, in any order. ---
  // A line in flight holds an entry of the line table, whose index is its request's
  // tag: what the line is for. A record's lines land in a record buffer, taken when its
  // job's first line leaves; a whole record goes to the IU.
  logic                 fetch_valid, fetch_ready, ref_valid, ref_ready;
  logic                 job_valid, job_ready;
  logic [JobBits-1:0]   job;
  logic [WorkBits-1:0]  work_d, work_q;  // refs fetched whose test has not left
  logic                 ref_credit, want_record, want_ref;
  logic [GotBits-1:0]   sent_d, sent_q;
  logic [1:0]           order_kind;
  logic [SlotBits-1:0]  order_slot;
  logic [WordSelBits-1:0] order_half;
  logic [IndexBits-1:0] order_k;
  logic [BufBits-1:0]   order_buf;
  logic [LineSelBits-1:0] order_line;
  logic [Slots-1:0]     fetch_grants, ref_grants;
  logic [3:0]           unused_picks;

  rpu_rr_arbiter #(.Inputs(Slots), .Width(1)) u_fetch_arb (
    .clk_i, .rst_ni,
    .valid_i(ready_mask), .ready_o(fetch_grants), .data_i('0),
    .valid_o(fetch_valid), .ready_i(fetch_ready), .data_o(unused_picks[0]), .index_o(fetch_slot)
  );
  rpu_rr_arbiter #(.Inputs(Slots), .Width(1)) u_ref_arb (
    .clk_i, .rst_ni,
    .valid_i(ref_mask), .ready_o(ref_grants), .data_i('0),
    .valid_o(ref_valid), .ready_i(ref_ready), .data_o(unused_picks[1]), .index_o(ref_slot)
  );

  logic [31:0] job_prim;
  assign job_prim = job[31:0];

  // The line table: the lowest free entry names the next request.
  logic [Lines-1:0]         line_busy_d, line_busy_q;
  logic [Lines*AskBits-1:0] asked_d, asked_q;
  logic [LineTagBits-1:0]       line_free, req_tag, held_tag_q, rsp_tag;
  logic                     line_room;
  always_comb begin : pick_free_line
    line_free = '0;
    line_room = 1'b0;
    for (int i = Lines - 1; i >= 0; i--) begin
      if (!line_busy_q[i]) begin
        line_free = LineTagBits'(i);
        line_room = 1'b1;
      end
    end
  end

  // The record buffers: the lowest free one takes a job's lines, the lowest whole one
  // that is its slot's next test goes to the IU.
  logic [Records-1:0]                      buf_busy_d, buf_busy_q, buf_whole;
  logic [Records*GotBits-1:0]              buf_got_d, buf_got_q;
  logic [Records*JobBits-1:0]              buf_job_d, buf_job_q;
  logic [Records*RecordLines*LineBits-1:0] buf_data_d, buf_data_q;
  logic [BufBits-1:0]                      buf_free, fill_buf_d, fill_buf_q, send_buf, test_buf, whole_buf;
  logic [BufBits-1:0]                      test_held_d, test_held_q;
  logic                                    buf_room, flight_valid, whole_any, test_hold_d, test_hold_q;
  always_comb begin : pick_buffers
    buf_free  = '0;
    buf_room  = 1'b0;
    whole_buf = '0;
    whole_any = 1'b0;
    for (int b = Records - 1; b >= 0; b--) begin
      if (!buf_busy_q[b]) begin
        buf_free = BufBits'(b);
        buf_room = 1'b1;
      end
      if (buf_whole[b]) begin
        whole_buf = BufBits'(b);
        whole_any = 1'b1;
      end
    end
  end
  // A record goes to the IU once per testing ray of its packet, in ray order; the
  // buffer whose tests have begun keeps the IU port until its last.
  assign test_buf     = test_hold_q ? test_held_q : whole_buf;
  assign flight_valid = test_hold_q || whole_any;
  assign test_hold_d  = test_issue ? !test_last : test_hold_q;
  assign test_held_d  = test_buf;
  assign send_buf = sent_q == '0 ? buf_free : fill_buf_q;

  // The request presented: a record line, else a ref, else a node; one not taken is
  // presented again with its tag (every source keeps its request until it is taken).
  logic [1:0] source, held_d, held_q;
  logic       hold_d, hold_q, go, req_taken;
  assign ref_credit  = work_q != WorkBits'(LeafDepth);
  assign want_record = job_valid && (sent_q != '0 || buf_room);
  assign want_ref    = ref_valid && ref_credit;
  assign source      = hold_q ? held_q : want_record ? KindRecord : want_ref ? KindRef : KindNode;
  assign go          = mem_req_ready_i && line_room;
  assign fetch_ready = go && source == KindNode;
  assign ref_ready   = go && source == KindRef;
  assign ref_issue   = ref_valid && ref_ready;
  assign fetch       = fetch_valid && fetch_ready;
  assign hold_d      = mem_req_valid_o && !mem_req_ready_i;
  assign held_d      = source;
  assign req_tag     = hold_q ? held_tag_q : line_free;
  assign req_taken   = mem_req_valid_o && mem_req_ready_i;

  logic [31:0] node_addr, ref_addr, record_addr;
  assign node_addr   = cfg_i.kd_nodes + 32'(node_all[32'(fetch_slot)*IndexBits +: IndexBits]) * rpu_pkg::KdNodeBytes;
  assign ref_addr    = cfg_i.prim_refs
                       + (first_all[32'(ref_slot)*32 +: 32] + 32'(k_all[32'(ref_slot)*IndexBits +: IndexBits]))
                         * rpu_pkg::PrimRefBytes;
  assign record_addr = cfg_i.isect_records + job_prim * RecordBytes + 32'(sent_q) * rpu_pkg::MemLineBytes;

  logic [AskBits-1:0] ask_in;
  always_comb begin : mem_request
    mem_req_o     = '0;
    mem_req_o.tag = rpu_pkg::CacheTagBits'(req_tag);
    unique case (source)
      KindRecord: begin
        mem_req_valid_o = want_record && line_room;
        mem_req_o.addr  = record_addr;
        ask_in          = {KindRecord, SlotBits'(0), WordSelBits'(0), IndexBits'(0), send_buf, LineSelBits'(sent_q)};
      end
      KindRef: begin
        mem_req_valid_o = want_ref && line_room;
        mem_req_o.addr  = {ref_addr[31:OffsetBits], OffsetBits'(0)};
        ask_in          = {KindRef, ref_slot, ref_addr[OffsetBits-1:2], k_all[32'(ref_slot)*IndexBits +: IndexBits],
                           BufBits'(0), LineSelBits'(0)};
      end
      default: begin
        mem_req_valid_o = fetch_valid && line_room;
        mem_req_o.addr  = {node_addr[31:OffsetBits], OffsetBits'(0)};
        ask_in          = {KindNode, fetch_slot, node_addr[OffsetBits-1:2], IndexBits'(0), BufBits'(0),
                           LineSelBits'(0)};
      end
    endcase
  end

  // The answered line: a node (kind, above or count; split or first), a ref, a record line.
  logic [31:0]            line_word, next_word;
  logic [WordSelBits-1:0] next_half;
  logic                   line_taken;
  assign mem_rsp_ready_o = 1'b1;  // every answer has its entry
  assign line_taken = mem_rsp_valid_i;
  assign rsp_tag    = mem_rsp_i.tag[LineTagBits-1:0];
  assign {order_kind, order_slot, order_half, order_k, order_buf, order_line} = asked_q[32'(rsp_tag)*AskBits +: AskBits];
  assign next_half  = order_half + WordSelBits'(1);
  assign line_word  = mem_rsp_i.data[32*order_half +: 32];
  assign next_word  = mem_rsp_i.data[32*next_half +: 32];
  assign line_slot  = order_slot;
  assign leaf_in    = line_taken && order_kind == KindNode && line_word[1:0] == 2'(rpu_pkg::KdNodeLeafKind);
  assign inner_in   = line_taken && order_kind == KindNode && line_word[1:0] != 2'(rpu_pkg::KdNodeLeafKind);
  assign leaf_count = line_word[31:2];
  assign leaf_first = next_word;

  for (genvar i = 0; i < Lines; i++) begin : g_line
    logic ask, answered;
    assign ask      = req_taken && req_tag == LineTagBits'(i);
    assign answered = line_taken && rsp_tag == LineTagBits'(i);
    assign line_busy_d[i] = ask || (line_busy_q[i] && !answered);
    assign asked_d[i*AskBits +: AskBits] = ask ? ask_in : asked_q[i*AskBits +: AskBits];
  end

  // A ref's prim becomes a record job in the lowest free entry of a table of LeafDepth,
  // as many as refs may be fetched ahead (work_q). Refs may be answered in any order, but
  // a slot's jobs leave the table in list order (its rec_k), and its whole records go to
  // the IU in list order (its test_k): a test never leaves with a t_best that a later
  // triangle of its leaf set, so an equal t keeps the lower list index, as the
  // sequential walk's strict compare does. The job whose lines go out stays picked until
  // its last line leaves (or while its first is held).
  logic [LeafDepth-1:0]         job_busy_d, job_busy_q;
  logic [LeafDepth*JobBits-1:0] jobs_d, jobs_q;
  logic [Slots*OrdBits-1:0]     rec_k_d, rec_k_q, test_k_d, test_k_q;
  logic [JobIndexBits-1:0]      job_free, job_next, job_pick, job_pick_q;
  logic                         job_room, job_next_valid, job_keep;
  always_comb begin : pick_jobs
    job_free       = '0;
    job_room       = 1'b0;
    job_next       = '0;
    job_next_valid = 1'b0;
    for (int j = LeafDepth - 1; j >= 0; j--) begin
      if (!job_busy_q[j]) begin
        job_free = JobIndexBits'(j);
        job_room = 1'b1;
      end
      if (job_busy_q[j] && jobs_q[j*JobBits + 32 +: OrdBits]
                           == rec_k_q[32'(jobs_q[j*JobBits + JobBits - 1 -: SlotBits])*OrdBits +: OrdBits]) begin
        job_next       = JobIndexBits'(j);
        job_next_valid = 1'b1;
      end
    end
  end
  assign job_keep  = sent_q != '0 || (hold_q && held_q == KindRecord);
  assign job_pick  = job_keep ? job_pick_q : job_next;
  assign job_valid = job_keep || job_next_valid;
  assign job       = jobs_q[32'(job_pick)*JobBits +: JobBits];

  logic record_go;
  assign record_go  = want_record && go && source == KindRecord;
  assign job_ready  = record_go && sent_q == GotBits'(RecordLines - 1);
  for (genvar j = 0; j < LeafDepth; j++) begin : g_job
    logic add;
    assign add = line_taken && order_kind == KindRef && job_free == JobIndexBits'(j);
    assign job_busy_d[j] = add || (job_busy_q[j] && !(job_ready && job_pick == JobIndexBits'(j)));
    assign jobs_d[j*JobBits +: JobBits] = add ? {order_slot, order_k, line_word} : jobs_q[j*JobBits +: JobBits];
  end
  for (genvar i = 0; i < Slots; i++) begin : g_order
    logic enter;
    assign enter = leaf_in && line_slot == SlotBits'(i);
    assign rec_k_d[i*OrdBits +: OrdBits] =
        enter ? '0 : rec_k_q[i*OrdBits +: OrdBits] + OrdBits'(job_ready && job[JobBits-1 -: SlotBits] == SlotBits'(i));
    assign test_k_d[i*OrdBits +: OrdBits] =
        enter ? '0 : test_k_q[i*OrdBits +: OrdBits] + OrdBits'(test_issue && test_last && test_slot == SlotBits'(i));
  end
  assign sent_d     = !record_go ? sent_q : job_ready ? '0 : sent_q + GotBits'(1);
  assign fill_buf_d = record_go ? send_buf : fill_buf_q;

  for (genvar b = 0; b < Records; b++) begin : g_record
    logic alloc, fill, free;
    logic [GotBits-1:0] got;
    assign got   = buf_got_q[b*GotBits +: GotBits];
    assign alloc = record_go && sent_q == '0 && send_buf == BufBits'(b);
    assign fill  = line_taken && order_kind == KindRecord && order_buf == BufBits'(b);
    assign free  = test_issue && test_last && test_buf == BufBits'(b);
    assign buf_busy_d[b] = alloc || (buf_busy_q[b] && !free);
    assign buf_got_d[b*GotBits +: GotBits] = alloc ? '0 : fill ? got + GotBits'(1) : got;
    assign buf_job_d[b*JobBits +: JobBits] = alloc ? job : buf_job_q[b*JobBits +: JobBits];
    logic [SlotBits-1:0] slot;
    logic [OrdBits-1:0]  k;
    assign slot = buf_job_q[b*JobBits + JobBits - 1 -: SlotBits];
    assign k    = buf_job_q[b*JobBits + 32 +: OrdBits];
    // Whole, and its slot's next test.
    assign buf_whole[b] = buf_busy_q[b] && got == GotBits'(RecordLines)
                          && k == test_k_q[32'(slot)*OrdBits +: OrdBits];
    for (genvar l = 0; l < RecordLines; l++) begin : g_line
      localparam int unsigned At = (b * RecordLines + l) * LineBits;
      assign buf_data_d[At +: LineBits] = fill && order_line == LineSelBits'(l) ? mem_rsp_i.data
                                                                                : buf_data_q[At +: LineBits];
    end
  end

  logic [JobBits-1:0] flight;
  assign flight    = buf_job_q[32'(test_buf)*JobBits +: JobBits];
  assign test_slot = flight[JobBits-1 -: SlotBits];

  // The ray the record goes to next: the packet's first testing ray from test_from_q on.
  logic [LaneBits-1:0] test_from_d, test_from_q;
  logic [P-1:0]        test_rays;
  assign test_rays = testing_all[32'(test_slot)*P +: P];
  assign test_lane = ray_from(test_rays, 32'(test_from_q));
  assign test_last = !any_ray_from(test_rays, 32'(test_lane) + 1);
  assign test_from_d = !test_issue ? test_from_q : test_last ? '0 : test_lane + LaneBits'(1);

  // ref_tests: the tests a ref's record owes, one per testing ray of its packet.
  always_comb begin : count_ref_tests
    ref_tests = '0;
    for (int r = 0; r < P; r++) ref_tests = ref_tests + ($clog2(P + 1))'(testing_all[32'(ref_slot)*P + 32'(r)]);
  end

  // --- The IU: a whole record leaves with an entry of the test table as its tag. ---
  logic [Tests-1:0]             test_busy_d, test_busy_q;
  logic [Tests*TestJobBits-1:0] table_d, table_q;
  logic [TestBits-1:0]          test_free;
  logic                         test_any_free;
  logic [TestBits-1:0]          answer_entry;
  always_comb begin : pick_free_test
    test_free     = '0;
    test_any_free = 1'b0;
    for (int i = Tests - 1; i >= 0; i--) begin
      if (!test_busy_q[i]) begin
        test_free     = TestBits'(i);
        test_any_free = 1'b1;
      end
    end
  end
  assign iu_req_valid_o = flight_valid && test_any_free;
  assign test_issue     = iu_req_valid_o && iu_req_ready_i;

  logic [31:0] test_ray;
  logic [1:0] test_axis_kx, test_axis_ky, test_axis_kz;
  assign test_ray = ray_at(test_slot, test_lane);
  assign {test_axis_kz, test_axis_ky, test_axis_kx} = axes_all[test_ray*6 +: 6];
  always_comb begin : iu_request
    iu_req_o.tag       = rpu_pkg::RayTagBits'(test_free);
    for (int a = 0; a < 3; a++) begin
      iu_req_o.origin[a*32 +: 32]    = 32'(pick_axis(origin_all, test_ray, 2'(a)));
      iu_req_o.direction[a*32 +: 32] = 32'(pick_axis(dir_all, test_ray, 2'(a)));
    end
    iu_req_o.t_min     = 32'(pick_w(t_min_all, test_ray));
    iu_req_o.t_best    = 32'(pick_w(best_all, test_ray));
    iu_req_o.kx        = test_axis_kx;
    iu_req_o.ky        = test_axis_ky;
    iu_req_o.kz        = test_axis_kz;
    iu_req_o.shear_x   = 32'(pick_w(shear_x_all, test_ray));
    iu_req_o.shear_y   = 32'(pick_w(shear_y_all, test_ray));
    iu_req_o.record    = '0;
    iu_req_o.record[RecordLines*LineBits-1:0] = buf_data_q[32'(test_buf)*RecordLines*LineBits +: RecordLines*LineBits];
  end

  // Answers: always taken, folded into the ray's nearest hit.
  logic [31:0] answer_ray;
  assign iu_rsp_ready_o = 1'b1;
  assign answer         = iu_rsp_valid_i;
  assign answer_entry   = iu_rsp_i.tag[TestBits-1:0];
  assign {answer_lane, answer_slot, answer_k, answer_prim} = table_q[32'(answer_entry)*TestJobBits +: TestJobBits];
  assign answer_ray     = ray_at(answer_slot, answer_lane);
  logic [W-1:0] answer_t, answer_best;
  assign answer_t    = iu_rsp_i.t[W-1:0];
  assign answer_best = pick_w(best_all, answer_ray);
  assign answer_wins = iu_rsp_i.hit
                       && (!hit_all[answer_ray] || fp_lt(answer_t, answer_best)
                           || (fp_eq(answer_t, answer_best)
                               && answer_k < best_k_all[answer_ray*IndexBits +: IndexBits]));

  for (genvar i = 0; i < Tests; i++) begin : g_test
    logic alloc;
    assign alloc = test_issue && test_free == TestBits'(i);
    assign test_busy_d[i] = alloc || (test_busy_q[i] && !(answer && answer_entry == TestBits'(i)));
    assign table_d[i*TestJobBits +: TestJobBits] = alloc ? {test_lane, flight} : table_q[i*TestJobBits +: TestJobBits];
  end
  assign work_d = work_q + WorkBits'(ref_issue) - WorkBits'(test_issue && test_last);

  // --- The node-step pipeline, a lane per ray of the packet. ---
  // Stage 0: an inner node's line, or else a leaf's end.
  logic [Slots-1:0] pop_grants;
  logic             pop_valid;
  rpu_rr_arbiter #(.Inputs(Slots), .Width(1)) u_pop_arb (
    .clk_i, .rst_ni,
    .valid_i(leaf_end_mask), .ready_o(pop_grants), .data_i('0),
    .valid_o(pop_valid), .ready_i(!inner_in), .data_o(unused_picks[2]), .index_o(pop_slot)
  );
  assign pop_enter = pop_valid && !inner_in;

  // A stage's carried fields: {valid, pop, slot, axis, above}.
  localparam int unsigned CarryBits = 2 + SlotBits + 2 + IndexBits;
  logic [CarryBits-1:0] s0, s1, s2, s3, s4;
  assign s0 = {inner_in || pop_enter, !inner_in, inner_in ? line_slot : pop_slot, line_word[1:0], line_word[31:2]};
  rpu_en_reg #(.Width(CarryBits)) u_s1 (.clk_i, .rst_ni, .en_i(1'b1), .data_i(s0), .data_o(s1));
  rpu_en_reg #(.Width(CarryBits)) u_s2 (.clk_i, .rst_ni, .en_i(1'b1), .data_i(s1), .data_o(s2));
  rpu_en_reg #(.Width(CarryBits)) u_s3 (.clk_i, .rst_ni, .en_i(1'b1), .data_i(s2), .data_o(s3));
  rpu_en_reg #(.Width(CarryBits)) u_s4 (.clk_i, .rst_ni, .en_i(1'b1), .data_i(s3), .data_o(s4));

  logic                 s1_valid, s1_pop, s2_valid, s2_pop, s3_valid, s3_pop, s4_valid, s4_pop;
  logic [SlotBits-1:0]  s1_slot, s2_slot, s3_slot, s4_slot;
  logic [1:0]           s1_axis, s2_axis, s3_axis, s4_axis;
  logic [IndexBits-1:0] s1_above, s2_above, s3_above, s4_above;
  assign {s1_valid, s1_pop, s1_slot, s1_axis, s1_above} = s1;
  assign {s2_valid, s2_pop, s2_slot, s2_axis, s2_above} = s2;
  assign {s3_valid, s3_pop, s3_slot, s3_axis, s3_above} = s3;
  assign {s4_valid, s4_pop, s4_slot, s4_axis, s4_above} = s4;

  // Stage 1: the split into the format, once for the packet.
  logic [W-1:0] split;
  rpu_fp_pipe_op #(.ExpBits(ExpBits), .FracBits(FracBits), .Op(rpu_pkg::FpOpFromFp32)) u_split (
    .clk_i, .rst_ni, .en_i(1'b1), .a_i(next_word), .b_i('0), .result_o(split)
  );
  // Stage 3 reads the stack's top for a leaf's end.
  logic [SlotBits+DepthBits-1:0] stack_raddr, stack_waddr;
  logic [EntryBits-1:0]          top3, top4, stack_wdata;
  logic [SpBits-1:0]             sp2, sp4;
  assign sp2         = sp_all[32'(s2_slot)*SpBits +: SpBits];
  assign stack_raddr = {s2_slot, DepthBits'(sp2 - SpBits'(1))};
  rpu_ram #(.Width(EntryBits), .Depth(Slots * StackDepth)) u_stack (
    .clk_i, .we_i(decide_push), .waddr_i(stack_waddr), .wdata_i(stack_wdata), .raddr_i(stack_raddr), .rdata_o(top3)
  );
  rpu_en_reg #(.Width(EntryBits)) u_top4 (.clk_i, .rst_ni, .en_i(1'b1), .data_i(top3), .data_o(top4));

  // Per ray: stage 2 O < s, O == s, s - O; stage 3 t_split = (s - O) * inv; stage 4
  // t_split <= t_far, t_split <= 0, t_split < t_near, or for a leaf's end t_best <= t_far
  // and t_best < the top entry's t_near.
  logic [P-1:0]   o_lt2, o_eq2, o_lt3, o_eq3, o_lt4, o_eq4, le_far, le_zero, lt_near;
  logic [P*W-1:0] t_split3, t_split4;
  for (genvar r = 0; r < P; r++) begin : g_step
    logic [W-1:0] o_axis, split_minus_o, t_split, cmp_a, near_b;
    logic [W-1:0] o_lt_bits, o_eq_bits, le_far_bits, le_zero_bits, lt_near_bits;
    assign o_axis = pick_axis(origin_all, ray_at(s1_slot, LaneBits'(r)), s1_axis);
    rpu_fp_pipe_op #(.ExpBits(ExpBits), .FracBits(FracBits), .Op(rpu_pkg::FpOpLt)) u_o_lt (
      .clk_i, .rst_ni, .en_i(1'b1), .a_i(32'(o_axis)), .b_i(32'(split)), .result_o(o_lt_bits)
    );
    rpu_fp_pipe_op #(.ExpBits(ExpBits), .FracBits(FracBits), .Op(rpu_pkg::FpOpEq)) u_o_eq (
      .clk_i, .rst_ni, .en_i(1'b1), .a_i(32'(o_axis)), .b_i(32'(split)), .result_o(o_eq_bits)
    );
    rpu_fp_pipe_op #(.ExpBits(ExpBits), .FracBits(FracBits), .Op(rpu_pkg::FpOpSub)) u_sub (
      .clk_i, .rst_ni, .en_i(1'b1), .a_i(32'(split)), .b_i(32'(o_axis)), .result_o(split_minus_o)
    );
    rpu_fp_pipe_op #(.ExpBits(ExpBits), .FracBits(FracBits), .Op(rpu_pkg::FpOpMul)) u_mul (
      .clk_i, .rst_ni, .en_i(1'b1), .a_i(32'(split_minus_o)),
      .b_i(32'(pick_axis(inv_all, ray_at(s2_slot, LaneBits'(r)), s2_axis))), .result_o(t_split)
    );
    assign o_lt2[r] = o_lt_bits[0];
    assign o_eq2[r] = o_eq_bits[0];
    assign t_split3[r*W +: W] = t_split;
    assign cmp_a  = s3_pop ? pick_w(best_all, ray_at(s3_slot, LaneBits'(r))) : t_split;
    assign near_b = s3_pop ? top3[r*2*W + W +: W] : pick_w(near_all, ray_at(s3_slot, LaneBits'(r)));
    rpu_fp_pipe_op #(.ExpBits(ExpBits), .FracBits(FracBits), .Op(rpu_pkg::FpOpLe)) u_le_far (
      .clk_i, .rst_ni, .en_i(1'b1), .a_i(32'(cmp_a)), .b_i(32'(pick_w(far_all, ray_at(s3_slot, LaneBits'(r))))),
      .result_o(le_far_bits)
    );
    rpu_fp_pipe_op #(.ExpBits(ExpBits), .FracBits(FracBits), .Op(rpu_pkg::FpOpLe)) u_le_zero (
      .clk_i, .rst_ni, .en_i(1'b1), .a_i(32'(t_split)), .b_i(32'(Zero)), .result_o(le_zero_bits)
    );
    rpu_fp_pipe_op #(.ExpBits(ExpBits), .FracBits(FracBits), .Op(rpu_pkg::FpOpLt)) u_lt_near (
      .clk_i, .rst_ni, .en_i(1'b1), .a_i(32'(cmp_a)), .b_i(32'(near_b)), .result_o(lt_near_bits)
    );
    assign le_far[r]  = le_far_bits[0];
    assign le_zero[r] = le_zero_bits[0];
    assign lt_near[r] = lt_near_bits[0];
    logic unused_bits;
    assign unused_bits = ^{o_lt_bits[W-1:1], o_eq_bits[W-1:1], le_far_bits[W-1:1], le_zero_bits[W-1:1],
                           lt_near_bits[W-1:1]};
  end

  // The origin's side carried to the decide stage with t_split, for every ray at once.
  rpu_en_reg #(.Width(2 * P)) u_o_flags3 (.clk_i, .rst_ni, .en_i(1'b1), .data_i({o_lt2, o_eq2}),
                                          .data_o({o_lt3, o_eq3}));
  rpu_en_reg #(.Width(2 * P + P * W)) u_carry4 (
    .clk_i, .rst_ni, .en_i(1'b1), .data_i({o_lt3, o_eq3, t_split3}), .data_o({o_lt4, o_eq4, t_split4})
  );

  // Decide: the packet's next node from its rays' steps (rpu_tu's StInnerEnd,
  // StLeafDecide and StPopDecide for each ray; docs/traversal.md "Packets").
  logic                 below_near, solo4, any_hit4, restart, finish, next_solo;
  logic [IndexBits-1:0] node4, near_child, far_child;
  logic [P-1:0]         active4, waiting4, valid4, hit4, below_first, to_near, to_far, both;
  logic [P-1:0]         lane_end, walking, popped, own4, deferred4;
  logic [LaneBits-1:0]  solo_lane4, first_valid, next_valid;
  logic [2:0]           signs4;
  assign decide      = s4_valid;
  assign decide_slot = s4_slot;
  assign sp4         = sp_all[32'(s4_slot)*SpBits +: SpBits];
  assign node4       = node_all[32'(s4_slot)*IndexBits +: IndexBits];
  assign active4     = active_all[32'(s4_slot)*P +: P];
  assign waiting4    = waiting_all[32'(s4_slot)*P +: P];
  assign valid4      = valid_all[32'(s4_slot)*P +: P];
  assign solo4       = solo_all[s4_slot];
  assign solo_lane4  = solo_lane_all[32'(s4_slot)*LaneBits +: LaneBits];
  assign any_hit4    = any_hit_all[s4_slot];
  assign signs4      = signs_all[32'(s4_slot)*3 +: 3];
  assign own4        = top4[2*W*P + P +: P];
  assign deferred4   = top4[2*W*P +: P];
  for (genvar r = 0; r < P; r++) begin : g_decide_ray
    assign hit4[r] = hit_all[ray_at(s4_slot, LaneBits'(r))];
    // The ray's own first child is the one below the split.
    assign below_first[r] = o_lt4[r] || (o_eq4[r] && dir_le0_all[ray_at(s4_slot, LaneBits'(r))*3 + 32'(s4_axis)]);
  end
  // The near child: below when the packet's inv on the axis is positive; alone, the
  // ray's own first child.
  assign below_near = solo4 ? below_first[solo_lane4] : !signs4[s4_axis];
  assign near_child  = below_near ? node4 + IndexBits'(1) : s4_above;
  assign far_child   = below_near ? s4_above : node4 + IndexBits'(1);
  assign stack_waddr = {s4_slot, DepthBits'(sp4)};
  assign first_valid = ray_from(valid4, 0);
  assign next_valid  = ray_from(valid4, 32'(solo_lane4) + 1);
  assign next_solo   = any_ray_from(valid4, 32'(solo_lane4) + 1);

  always_comb begin : decide_step
    decide_node      = node4;
    decide_phase     = PhReady;
    decide_push      = 1'b0;
    decide_pop       = 1'b0;
    decide_active    = active4;
    decide_waiting   = waiting4;
    decide_solo      = solo4;
    decide_solo_lane = solo_lane4;
    decide_near_we   = '0;
    decide_far_we    = '0;
    decide_fault     = '0;
    decide_reset     = '0;
    decide_near      = '0;
    decide_far       = '0;
    stack_wdata      = '0;
    stack_wdata[EntryBits-1 -: IndexBits] = far_child;
    restart  = 1'b0;
    finish   = 1'b0;
    to_near  = '0;
    to_far   = '0;
    both     = '0;
    lane_end = '0;
    walking  = '0;
    popped   = '0;
    if (!s4_pop) begin
      for (int r = 0; r < P; r++) begin
        if (active4[r]) begin
          if (!le_far[r] || le_zero[r]) begin
            // Only the first child: the plane is behind, beyond, or (NaN) holds the ray.
            if (below_first[r] == below_near) to_near[r] = 1'b1;
            else to_far[r] = 1'b1;
          end else if (lt_near[r]) begin
            if (below_first[r] == below_near) to_far[r] = 1'b1;
            else to_near[r] = 1'b1;
          end else begin
            both[r] = 1'b1;
            if (below_first[r] != below_near) restart = 1'b1;
          end
        end
      end
      if (!restart) begin
        if ((to_near | both) == '0) begin
          decide_node = far_child;  // every active ray goes on to the far child alone
        end else begin
          decide_node = near_child;
          if ((to_far | both) != '0) begin
            if (sp4 == SpBits'(StackDepth)) begin
              if (solo4) begin
                decide_fault[solo_lane4] = 1'b1;  // a ray alone faults where its own walk does
                finish = 1'b1;
              end else begin
                restart = 1'b1;
              end
            end else begin
              decide_push    = s4_valid;
              decide_active  = active4 & ~to_far;
              decide_waiting = waiting4 | to_far;
              stack_wdata[2*W*P + P +: P] = both;
              stack_wdata[2*W*P +: P]     = to_far;
              for (int r = 0; r < P; r++) begin
                if (both[r]) begin
                  stack_wdata[r*2*W + W +: W] = t_split4[r*W +: W];
                  stack_wdata[r*2*W +: W]     = pick_w(far_all, ray_at(s4_slot, LaneBits'(r)));
                  decide_far_we[r]            = 1'b1;
                  decide_far[r*W +: W]        = t_split4[r*W +: W];
                end else if (to_far[r]) begin
                  stack_wdata[r*2*W + W +: W] = pick_w(near_all, ray_at(s4_slot, LaneBits'(r)));
                  stack_wdata[r*2*W +: W]     = pick_w(far_all, ray_at(s4_slot, LaneBits'(r)));
                end
              end
            end
          end
        end
      end
    end else begin
      // A leaf's end: a ray whose hit lies within its interval (any hit, for any-hit
      // rays) is done; the others wait for an entry of theirs.
      lane_end       = active4 & hit4 & (any_hit4 ? '1 : le_far);
      walking        = waiting4 | (active4 & ~lane_end);
      decide_active  = '0;
      decide_waiting = walking;
      if (walking == '0 || sp4 == '0) begin
        finish = 1'b1;
      end else begin
        // Pop: the entry's rays take its interval, but a ray that pushed it and whose
        // hit is nearer than its t_near is done.
        decide_pop     = 1'b1;
        popped         = (own4 | deferred4) & walking;
        decide_waiting = walking & ~popped;
        for (int r = 0; r < P; r++) begin
          if (popped[r] && !(own4[r] && hit4[r] && lt_near[r])) begin
            decide_active[r]     = 1'b1;
            decide_near_we[r]    = 1'b1;
            decide_far_we[r]     = 1'b1;
            decide_near[r*W +: W] = top4[r*2*W + W +: W];
            decide_far[r*W +: W]  = top4[r*2*W +: W];
          end
        end
        if (decide_active != '0) begin
          decide_node = top4[EntryBits-1 -: IndexBits];
        end else if (decide_waiting != '0) begin
          decide_phase = PhLeafEnd;  // pop again
        end else begin
          finish = 1'b1;
        end
      end
    end
    if (restart || (finish && solo4 && next_solo)) begin
      // Walk a ray alone from the root: the packet's first after an overflow, the next
      // after a ray alone ends.
      decide_push      = 1'b0;
      decide_solo      = 1'b1;
      decide_solo_lane = restart ? first_valid : next_valid;
      decide_reset     = '0;
      decide_reset[decide_solo_lane] = 1'b1;
      decide_active    = decide_reset;
      decide_waiting   = '0;
      decide_node      = '0;
      decide_phase     = PhReady;
    end else if (finish) begin
      decide_phase = PhDone;
    end
  end

  // --- Finish: round robin among the finished packets, then their rays one a cycle. ---
  logic fin_valid_d, fin_valid_q, fin_pick_valid, fin_ready, fin_rsp_taken, fin_last;
  logic [SlotBits-1:0] fin_slot_d;
  logic [LaneBits-1:0] fin_lane_d, fin_lane_q, fin_first, fin_next;
  logic [Slots-1:0]    fin_grants;
  logic [P-1:0]        fin_take_rays, fin_rays;
  rpu_rr_arbiter #(.Inputs(Slots), .Width(1)) u_fin_arb (
    .clk_i, .rst_ni,
    .valid_i(done_mask), .ready_o(fin_grants), .data_i('0),
    .valid_o(fin_pick_valid), .ready_i(fin_ready), .data_o(unused_picks[3]), .index_o(fin_take_slot)
  );
  assign fin_take_rays = valid_all[32'(fin_take_slot)*P +: P];
  assign fin_rays      = valid_all[32'(fin_slot_q)*P +: P];
  assign fin_first   = ray_from(fin_take_rays, 0);
  assign fin_next    = ray_from(fin_rays, 32'(fin_lane_q) + 1);
  assign fin_last    = !any_ray_from(fin_rays, 32'(fin_lane_q) + 1);
  assign fin_done    = fin_rsp_taken && fin_last;
  assign fin_ready   = !fin_valid_q || fin_done;
  assign fin_take    = fin_pick_valid && fin_ready;
  assign fin_valid_d = fin_take || (fin_valid_q && !fin_done);
  assign fin_slot_d  = fin_take ? fin_take_slot : fin_slot_q;
  assign fin_lane_d  = fin_take ? fin_first : fin_rsp_taken ? fin_next : fin_lane_q;

  // §6: t, u, v widened to fp32 (exact), t back to world space.
  logic [31:0] fin_ray;
  assign fin_ray = ray_at(fin_slot_q, fin_lane_q);
  logic [31:0] wide_t, wide_u, wide_v, world_t;
  rpu_fp_misc_core #(.ExpBits(ExpBits), .FracBits(FracBits)) u_wide_t (
    .op_i(rpu_pkg::FpOpToFp32), .a_i(32'(pick_w(best_all, fin_ray))), .b_i('0), .result_o(wide_t)
  );
  rpu_fp_misc_core #(.ExpBits(ExpBits), .FracBits(FracBits)) u_wide_u (
    .op_i(rpu_pkg::FpOpToFp32), .a_i(32'(pick_w(u_all, fin_ray))), .b_i('0), .result_o(wide_u)
  );
  rpu_fp_misc_core #(.ExpBits(ExpBits), .FracBits(FracBits)) u_wide_v (
    .op_i(rpu_pkg::FpOpToFp32), .a_i(32'(pick_w(v_all, fin_ray))), .b_i('0), .result_o(wide_v)
  );
  logic signed [9:0] to_world_exp;
  assign to_world_exp = {{2{cfg_i.kd_scale_exponent[7]}}, cfg_i.kd_scale_exponent};
  rpu_fp32_scale u_t_out (.value_i(wide_t), .exp_i(to_world_exp), .value_o(world_t));

  rpu_pkg::tu_rsp_t fin_rsp;
  assign fin_rsp.tag    = tag_all[fin_ray*rpu_pkg::RayTagBits +: rpu_pkg::RayTagBits];
  assign fin_rsp.hit    = hit_all[fin_ray];
  assign fin_rsp.t      = world_t;
  assign fin_rsp.u      = wide_u;
  assign fin_rsp.v      = wide_v;
  assign fin_rsp.prim   = hit_prim_all[fin_ray*32 +: 32];
  assign fin_rsp.nodes  = nodes_all[fin_ray*32 +: 32];
  assign fin_rsp.leaves = leaves_all[fin_ray*32 +: 32];
  assign fin_rsp.tests  = tests_all[fin_ray*32 +: 32];
  assign fin_rsp.fault  = fault_all[fin_ray];

  // Responses: the finish stage's and the set-up engines' (rays that miss the box).
  logic [Setups:0]                       out_valid, out_ready;
  logic [(Setups+1)*rpu_pkg::TuRspBits-1:0] out_data;
  logic [$clog2(Setups + 1)-1:0]         out_index;
  assign out_valid = {setup_rsp_valid, fin_valid_q};
  assign out_data  = {setup_out, fin_rsp};
  assign {setup_rsp_ready, fin_rsp_taken} = out_ready;
  rpu_rr_arbiter #(.Inputs(Setups + 1), .Width(rpu_pkg::TuRspBits)) u_rsp_arb (
    .clk_i, .rst_ni,
    .valid_i(out_valid), .ready_o(out_ready), .data_i(out_data),
    .valid_o(rsp_valid_o), .ready_i(rsp_ready_i), .data_o(rsp_o), .index_o(out_index)
  );

  always_ff @(posedge clk_i or negedge rst_ni) begin : regs
    if (!rst_ni) begin
      hold_q         <= 1'b0;
      held_q         <= KindNode;
      work_q         <= '0;
      held_tag_q     <= '0;
      sent_q         <= '0;
      line_busy_q    <= '0;
      asked_q        <= '0;
      buf_busy_q     <= '0;
      buf_got_q      <= '0;
      buf_job_q      <= '0;
      buf_data_q     <= '0;
      fill_buf_q     <= '0;
      job_busy_q     <= '0;
      jobs_q         <= '0;
      job_pick_q     <= '0;
      rec_k_q        <= '0;
      test_k_q       <= '0;
      test_hold_q    <= 1'b0;
      test_held_q    <= '0;
      test_from_q    <= '0;
      test_busy_q    <= '0;
      table_q        <= '0;
      form_open_q    <= 1'b0;
      form_any_hit_q <= 1'b0;
      form_slot_q    <= '0;
      form_rays_q    <= '0;
      form_seq_q     <= '0;
      form_signs_q   <= '0;
      fin_valid_q    <= 1'b0;
      fin_slot_q     <= '0;
      fin_lane_q     <= '0;
    end else begin
      hold_q         <= hold_d;
      held_q         <= held_d;
      work_q         <= work_d;
      held_tag_q     <= req_tag;
      sent_q         <= sent_d;
      line_busy_q    <= line_busy_d;
      asked_q        <= asked_d;
      buf_busy_q     <= buf_busy_d;
      buf_got_q      <= buf_got_d;
      buf_job_q      <= buf_job_d;
      buf_data_q     <= buf_data_d;
      fill_buf_q     <= fill_buf_d;
      job_busy_q     <= job_busy_d;
      jobs_q         <= jobs_d;
      job_pick_q     <= job_pick;
      rec_k_q        <= rec_k_d;
      test_k_q       <= test_k_d;
      test_hold_q    <= test_hold_d;
      test_held_q    <= test_held_d;
      test_from_q    <= test_from_d;
      test_busy_q    <= test_busy_d;
      table_q        <= table_d;
      form_open_q    <= form_open_d;
      form_any_hit_q <= form_any_hit_d;
      form_slot_q    <= form_slot_d;
      form_rays_q    <= form_rays_d;
      form_seq_q     <= form_seq_d;
      form_signs_q   <= form_signs_d;
      fin_valid_q    <= fin_valid_d;
      fin_slot_q     <= fin_slot_d;
      fin_lane_q     <= fin_lane_d;
    end
  end

  // Bits the unit does not read: the picks' grants (the index is what counts), the
  // FIFOs' readiness (room is guaranteed by work_q), the set-up engines' idle ports,
  // the start rays' records, address bits below a line, the IU tag above the table.
  logic unused;
  assign unused = ^{fetch_grants, ref_grants, pop_grants, fin_grants, unused_picks, job_room, mem_rsp_i.tag,
                    unused_setup_ports, start_index, out_index, given_ray.record, node_addr[1:0],
                    ref_addr[1:0], s1_above, s2_above, s3_above, s1_pop, s2_pop, s1_valid, s2_valid,
                    s3_valid, s3_axis, s4_above, dir_all, lane_end, waiting_all};
  if (W < 32) begin : g_unused_high
    logic unused_high;
    assign unused_high = ^{given_near[31:W], given_far[31:W]};
  end

`ifndef SYNTHESIS
  initial begin
    assert (Slots >= 2 && (1 << SlotBits) == Slots) else $error("rpu_tu_pipe: Slots %0d is not a power of two >= 2", Slots);
    assert (Packet >= 1 && Packet <= 8 && (Packet == 1 || (1 << LaneBits) == Packet))
      else $error("rpu_tu_pipe: Packet %0d is not a power of two in 1..8", Packet);
    assert (SlotBits + LaneBits <= rpu_pkg::RayTagBits && ArrBits <= rpu_pkg::RayTagBits)
      else $error("rpu_tu_pipe: %0d slots of %0d rays outgrow the ray tag", Slots, Packet);
    assert ((1 << DepthBits) == StackDepth) else $error("rpu_tu_pipe: StackDepth %0d is not a power of two", StackDepth);
    assert (LineTagBits >= 1 && LineTagBits <= rpu_pkg::CacheTagBits)
      else $error("rpu_tu_pipe: LineTagBits %0d outside 1..%0d", LineTagBits, rpu_pkg::CacheTagBits);
    assert (Records >= 2 && (1 << BufBits) == Records) else $error("rpu_tu_pipe: Records %0d is not a power of two >= 2", Records);
    assert (Tests <= (1 << rpu_pkg::RayTagBits) && (1 << TestBits) == Tests)
      else $error("rpu_tu_pipe: Tests %0d is not a power of two the IU tag holds", Tests);
  end
  always_ff @(posedge clk_i) begin : check_fifos_and_answers
    if (rst_ni) begin
      // The job table never overflows (at most LeafDepth refs between request and test).
      assert (!(line_taken && order_kind == KindRef) || job_room)
        else $error("rpu_tu_pipe: record job table full");
      assert (!mem_rsp_valid_i || (32'(mem_rsp_i.tag) < Lines && line_busy_q[rsp_tag]))
        else $error("rpu_tu_pipe: a memory answer with tag %0h for no line in flight", mem_rsp_i.tag);
      assert (!iu_rsp_valid_i || test_busy_q[answer_entry])
        else $error("rpu_tu_pipe: IU answer tag %0d names no test in flight", iu_rsp_i.tag);
      // A record in the IU port's buffer is tested by at least one ray of its packet.
      assert (!flight_valid || test_rays != '0)
        else $error("rpu_tu_pipe: a whole record of slot %0d with no ray to test it", test_slot);
    end
  end
`endif

endmodule
