// A traversal unit that keeps Slots rays in flight: one rpu_tu walker per ray slot, each
// with its own state, registers and stack (the stacks banked by slot), sharing the
// unit's ports. While one slot waits for a node line or an IU answer the others step,
// so memory and IU latency are hidden by other rays (docs/rtl.md, "Ray slots").
//
//   ray requests  go to the lowest free slot; a slot is free from its response's
//                 hand-over until it is given the next ray.
//   responses     round robin among the slots that have one (rpu_rr_arbiter), so rays
//                 leave in any order, each with its own tag.
//   memory        requests round robin, tagged 0; the slot of each request taken enters
//                 a FIFO, and the in-order responses go to the slot at its head.
//   IU            tests round robin, the IU tag replaced by the slot's index; an answer
//                 goes to the slot its tag names, so answers may come in any order.
//
// Every slot's walk is rpu_tu's, so each ray's result, counters and fault are the
// golden model's whatever the other slots do. Slots = 1 is rpu_tu itself. Pipe = 1
// makes the unit rpu_tu_pipe instead: the slots share one node-step pipeline, with
// Setups set-up engines (docs/rtl.md "The node-step pipeline"); the ray unit and the
// co-simulation top choose by these parameters alone.
module rpu_tu_slots #(
  parameter int unsigned ExpBits    = rpu_pkg::FormatFp32ExponentBits,
  parameter int unsigned FracBits   = rpu_pkg::FormatFp32FractionBits,
  parameter int unsigned IsectMode  = rpu_pkg::IsectModeWoop,
  parameter int unsigned StackDepth = rpu_pkg::ConfigDefaultStackDepth,
  parameter int unsigned Slots      = 1,
  parameter int unsigned Pipe       = 0,
  parameter int unsigned Packet     = 1,  // with Pipe: rays a slot walks together
  parameter int unsigned Setups     = 2,
  parameter int unsigned LineTagBits = 4  // with Pipe: lines in flight on the memory port, 2^LineTagBits
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

  // At module scope: Yosys 0.23 does not resolve a generate block's localparam in a
  // cast inside a loop nested in that block.
  localparam int unsigned TagBits = rpu_pkg::RayTagBits;

  if (Pipe != 0) begin : g_pipe
    rpu_tu_pipe #(.ExpBits(ExpBits), .FracBits(FracBits), .IsectMode(IsectMode), .StackDepth(StackDepth),
                  .Slots(Slots), .Packet(Packet), .Setups(Setups), .LineTagBits(LineTagBits)) u_pipe (
      .clk_i, .rst_ni, .cfg_i,
      .req_valid_i, .req_ready_o, .req_i,
      .rsp_valid_o, .rsp_ready_i, .rsp_o,
      .mem_req_valid_o, .mem_req_ready_i, .mem_req_o,
      .mem_rsp_valid_i, .mem_rsp_ready_o, .mem_rsp_i,
      .iu_req_valid_o, .iu_req_ready_i, .iu_req_o,
      .iu_rsp_valid_i, .iu_rsp_ready_o, .iu_rsp_i
    );
  end else if (Slots == 1) begin : g_one
    // The start port is rpu_tu's HandOff, which a walker does not use.
    logic             start_valid, start_any_hit;
    rpu_pkg::iu_req_t start_ray;
    logic [95:0]      start_inv;
    logic [31:0]      start_near, start_far;
    logic [2:0]       start_dir_le0;
    logic             unused_start;
    rpu_tu #(.ExpBits(ExpBits), .FracBits(FracBits), .IsectMode(IsectMode), .StackDepth(StackDepth)) u_walker (
      .clk_i, .rst_ni, .cfg_i,
      .req_valid_i, .req_ready_o, .req_i,
      .rsp_valid_o, .rsp_ready_i, .rsp_o,
      .mem_req_valid_o, .mem_req_ready_i, .mem_req_o,
      .mem_rsp_valid_i, .mem_rsp_ready_o, .mem_rsp_i,
      .iu_req_valid_o, .iu_req_ready_i, .iu_req_o,
      .iu_rsp_valid_i, .iu_rsp_ready_o, .iu_rsp_i,
      .start_valid_o(start_valid), .start_ready_i(1'b0), .start_ray_o(start_ray), .start_inv_o(start_inv),
      .start_t_near_o(start_near), .start_t_far_o(start_far), .start_any_hit_o(start_any_hit),
      .start_dir_le0_o(start_dir_le0)
    );
    assign unused_start = ^{start_valid, start_ray, start_inv, start_near, start_far, start_any_hit, start_dir_le0};
  end else begin : g_slots
    localparam int unsigned SlotBits = $clog2(Slots);
    // A walker has at most one intersection record's lines in flight.
    localparam int unsigned RecordBytes = IsectMode == rpu_pkg::IsectModeWatertight
                                          ? rpu_pkg::TriangleRecordWatertightBytes
                                          : rpu_pkg::TriangleRecordWoopBytes;
    localparam int unsigned LinesPerSlot = RecordBytes / rpu_pkg::MemLineBytes;

    // rpu_tu's valids never depend on its readies, but its one output process reads
    // both, so Verilator sees a loop through each arbiter's grant; there is none.
    /* verilator lint_off UNOPTFLAT */
    logic [Slots-1:0]                        req_valid, req_ready, rsp_valid, rsp_ready;
    logic [Slots-1:0]                        mem_req_valid, mem_req_ready, mem_rsp_valid, mem_rsp_ready;
    logic [Slots-1:0]                        iu_req_valid, iu_req_ready, iu_rsp_valid, iu_rsp_ready;
    /* verilator lint_on UNOPTFLAT */
    logic [Slots*rpu_pkg::TuRspBits-1:0]     rsp;
    logic [Slots*rpu_pkg::MemReqBits-1:0]    mem_req;
    logic [Slots*rpu_pkg::IuReqBits-1:0]     iu_req;

    for (genvar i = 0; i < Slots; i++) begin : g_walker
      rpu_pkg::tu_rsp_t  walker_rsp;
      rpu_pkg::mem_req_t walker_mem_req;
      rpu_pkg::iu_req_t  walker_iu_req;
      // The start port is rpu_tu's HandOff, which a walker does not use.
      logic              start_valid, start_any_hit;
      rpu_pkg::iu_req_t  start_ray;
      logic [95:0]       start_inv;
      logic [31:0]       start_near, start_far;
      logic [2:0]        start_dir_le0;
      logic              unused_start;
      rpu_tu #(.ExpBits(ExpBits), .FracBits(FracBits), .IsectMode(IsectMode), .StackDepth(StackDepth)) u_walker (
        .clk_i, .rst_ni, .cfg_i,
        .req_valid_i(req_valid[i]), .req_ready_o(req_ready[i]), .req_i,
        .rsp_valid_o(rsp_valid[i]), .rsp_ready_i(rsp_ready[i]), .rsp_o(walker_rsp),
        .mem_req_valid_o(mem_req_valid[i]), .mem_req_ready_i(mem_req_ready[i]), .mem_req_o(walker_mem_req),
        .mem_rsp_valid_i(mem_rsp_valid[i]), .mem_rsp_ready_o(mem_rsp_ready[i]), .mem_rsp_i,
        .iu_req_valid_o(iu_req_valid[i]), .iu_req_ready_i(iu_req_ready[i]), .iu_req_o(walker_iu_req),
        .iu_rsp_valid_i(iu_rsp_valid[i]), .iu_rsp_ready_o(iu_rsp_ready[i]), .iu_rsp_i,
        .start_valid_o(start_valid), .start_ready_i(1'b0), .start_ray_o(start_ray), .start_inv_o(start_inv),
        .start_t_near_o(start_near), .start_t_far_o(start_far), .start_any_hit_o(start_any_hit),
        .start_dir_le0_o(start_dir_le0)
      );
      assign unused_start = ^{start_valid, start_ray, start_inv, start_near, start_far, start_any_hit, start_dir_le0};
      assign rsp[i*rpu_pkg::TuRspBits +: rpu_pkg::TuRspBits]     = walker_rsp;
      assign mem_req[i*rpu_pkg::MemReqBits +: rpu_pkg::MemReqBits] = walker_mem_req;
      assign iu_req[i*rpu_pkg::IuReqBits +: rpu_pkg::IuReqBits]   = walker_iu_req;
    end

    // --- Rays in: the lowest free slot. ---
    logic [Slots-1:0]    busy_d, busy_q;
    logic [SlotBits-1:0] free;
    logic                any_free;
    always_comb begin : pick_free_slot
      free     = '0;
      any_free = 1'b0;
      for (int i = Slots - 1; i >= 0; i--) begin
        if (!busy_q[i]) begin
          free     = SlotBits'(i);
          any_free = 1'b1;
        end
      end
    end
    for (genvar i = 0; i < Slots; i++) begin : g_req
      assign req_valid[i] = req_valid_i && any_free && free == SlotBits'(i);
    end
    assign req_ready_o = any_free && req_ready[free];

    // --- Responses out. ---
    logic [SlotBits-1:0] rsp_slot;
    rpu_rr_arbiter #(.Inputs(Slots), .Width(rpu_pkg::TuRspBits)) u_rsp_arb (
      .clk_i, .rst_ni,
      .valid_i(rsp_valid), .ready_o(rsp_ready), .data_i(rsp),
      .valid_o(rsp_valid_o), .ready_i(rsp_ready_i), .data_o(rsp_o), .index_o(rsp_slot)
    );
    always_comb begin : next_busy
      busy_d = busy_q;
      if (rsp_valid_o && rsp_ready_i) busy_d[rsp_slot] = 1'b0;
      if (req_valid_i && req_ready_o) busy_d[free] = 1'b1;
    end

    // --- Memory: requests round robin, responses in order to the slot that asked. ---
    logic                mem_arb_valid, mem_arb_ready, order_ready, order_valid;
    logic [SlotBits-1:0] mem_slot, order_slot;
    rpu_rr_arbiter #(.Inputs(Slots), .Width(rpu_pkg::MemReqBits)) u_mem_arb (
      .clk_i, .rst_ni,
      .valid_i(mem_req_valid), .ready_o(mem_req_ready), .data_i(mem_req),
      .valid_o(mem_arb_valid), .ready_i(mem_arb_ready), .data_o(mem_req_o), .index_o(mem_slot)
    );
    assign mem_req_valid_o = mem_arb_valid && order_ready;
    assign mem_arb_ready   = mem_req_ready_i && order_ready;
    rpu_fifo #(.Width(SlotBits), .Depth(Slots * LinesPerSlot)) u_order (
      .clk_i, .rst_ni,
      .in_valid_i(mem_req_valid_o && mem_req_ready_i), .in_ready_o(order_ready), .in_data_i(mem_slot),
      .out_valid_o(order_valid), .out_ready_i(mem_rsp_valid_i && mem_rsp_ready_o), .out_data_o(order_slot)
    );
    for (genvar i = 0; i < Slots; i++) begin : g_mem_rsp
      assign mem_rsp_valid[i] = mem_rsp_valid_i && order_valid && order_slot == SlotBits'(i);
    end
    assign mem_rsp_ready_o = order_valid && mem_rsp_ready[order_slot];

    // --- IU: tests round robin, the tag replaced by the slot's index; answers by tag. ---
    rpu_pkg::iu_req_t    iu_test;
    logic [SlotBits-1:0] iu_slot;
    logic [SlotBits-1:0] answer_slot;
    rpu_rr_arbiter #(.Inputs(Slots), .Width(rpu_pkg::IuReqBits)) u_iu_arb (
      .clk_i, .rst_ni,
      .valid_i(iu_req_valid), .ready_o(iu_req_ready), .data_i(iu_req),
      .valid_o(iu_req_valid_o), .ready_i(iu_req_ready_i), .data_o(iu_test), .index_o(iu_slot)
    );
    always_comb begin : iu_request
      iu_req_o     = iu_test;
      iu_req_o.tag = TagBits'(iu_slot);
    end
    assign answer_slot = iu_rsp_i.tag[SlotBits-1:0];
    for (genvar i = 0; i < Slots; i++) begin : g_iu_rsp
      assign iu_rsp_valid[i] = iu_rsp_valid_i && answer_slot == SlotBits'(i);
    end
    assign iu_rsp_ready_o = iu_rsp_ready[answer_slot];

    // The IU's tag bits above the slot index are zero (the assertion below); the walkers'
    // own tags are replaced (iu_test whole: Yosys 0.23 reads no field of a struct declared
    // in a generate block).
    logic unused_tag;
    assign unused_tag = ^{iu_test, iu_rsp_i.tag};

    always_ff @(posedge clk_i or negedge rst_ni) begin : regs
      if (!rst_ni) begin
        busy_q <= '0;
      end else begin
        busy_q <= busy_d;
      end
    end

`ifndef SYNTHESIS
    // An answer names a slot that has a test out; a memory response has a requester.
    always_ff @(posedge clk_i) begin : check_answers
      if (rst_ni && iu_rsp_valid_i) begin
        assert (iu_rsp_i.tag < TagBits'(Slots))
          else $error("rpu_tu_slots: IU answer tag %0d names no slot (%0d slots)", iu_rsp_i.tag, Slots);
      end
      if (rst_ni && mem_rsp_valid_i) begin
        assert (order_valid) else $error("rpu_tu_slots: a memory response no slot asked for");
      end
    end
`endif
  end

endmodule
