// A traversal unit with its intersection unit: what a `trace` instruction hands a ray
// to. The TU walks the kd tree over the memory port and sends each leaf triangle to
// rpu_iu; the ray's hit record comes back on the response port (docs/rtl.md, "Ray
// unit"). The TU is rpu_tu_slots (TuSlots walkers), or with TuPipe = 1 rpu_tu_pipe
// (TuSlots slots sharing a node-step pipeline, TuSetups set-up engines). Wiring, and the
// counters of its time and work (docs/chip.md "Statistics"): both units are the ones
// co-simulated alone.
module rpu_ray_unit #(
  parameter int unsigned ExpBits    = rpu_pkg::FormatFp32ExponentBits,
  parameter int unsigned FracBits   = rpu_pkg::FormatFp32FractionBits,
  parameter int unsigned IsectMode  = rpu_pkg::IsectModeWoop,
  parameter int unsigned StackDepth = rpu_pkg::ConfigDefaultStackDepth,
  parameter int unsigned TuSlots    = 1,
  parameter int unsigned TuPipe     = 0,
  parameter int unsigned TuPacket   = 1,  // with TuPipe: rays a slot walks together
  parameter int unsigned TuSetups   = 2,
  parameter int unsigned LineTagBits = 4  // with TuPipe: lines in flight on the memory port, 2^LineTagBits
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

  // The unit's time and work, counted in the cycles count_i is high (the chip's frame).
  input  logic                         count_i,
  output rpu_pkg::ray_unit_counters_t  counters_o
);

  logic             iu_req_valid, iu_req_ready;
  rpu_pkg::iu_req_t iu_req;
  logic             iu_rsp_valid, iu_rsp_ready;
  rpu_pkg::iu_rsp_t iu_rsp;

  // The TU's clock runs while a ray is offered or in the unit, or a line or a test it
  // asked for is out (rpu_clock_gate; the counts are the counters' below): without
  // them it has nothing to do.
  logic tu_clk;

  rpu_tu_slots #(.ExpBits(ExpBits), .FracBits(FracBits), .IsectMode(IsectMode), .StackDepth(StackDepth),
                 .Slots(TuSlots), .Pipe(TuPipe), .Packet(TuPacket), .Setups(TuSetups), .LineTagBits(LineTagBits)) u_tu (
    .clk_i(tu_clk), .rst_ni, .cfg_i,
    .req_valid_i, .req_ready_o, .req_i,
    .rsp_valid_o, .rsp_ready_i, .rsp_o,
    .mem_req_valid_o, .mem_req_ready_i, .mem_req_o,
    .mem_rsp_valid_i, .mem_rsp_ready_o, .mem_rsp_i,
    .iu_req_valid_o(iu_req_valid), .iu_req_ready_i(iu_req_ready), .iu_req_o(iu_req),
    .iu_rsp_valid_i(iu_rsp_valid), .iu_rsp_ready_o(iu_rsp_ready), .iu_rsp_i(iu_rsp)
  );

  // A skid buffer between the TU's test requests and the IU: the IU's ready follows its
  // answer's (a test starts as the last one leaves) and rpu_tu decides all its outputs in
  // one process, so without registers between them the two would form a combinational
  // loop (as Verilator sees it with --assert), evaluated over and over each cycle.
  logic             iu_in_valid, iu_in_ready;
  rpu_pkg::iu_req_t iu_in;
  rpu_skid_buf #(.Width(rpu_pkg::IuReqBits)) u_iu_req (
    .clk_i, .rst_ni,
    .valid_i(iu_req_valid), .ready_o(iu_req_ready), .data_i(iu_req),
    .valid_o(iu_in_valid), .ready_i(iu_in_ready), .data_o(iu_in)
  );

  rpu_iu #(.ExpBits(ExpBits), .FracBits(FracBits), .IsectMode(IsectMode)) u_iu (
    .clk_i, .rst_ni,
    .req_valid_i(iu_in_valid), .req_ready_o(iu_in_ready), .req_i(iu_in),
    .rsp_valid_o(iu_rsp_valid), .rsp_ready_i(iu_rsp_ready), .rsp_o(iu_rsp)
  );

  // ---------------------------------------------------------------------------------
  // Counters: a ray is in the unit from its request to its answer; meanwhile the unit
  // waits for memory while a line read is asked for and unanswered, for the IU while a
  // test is, and is busy otherwise. The work is the answers' own counts, summed.
  // ---------------------------------------------------------------------------------
  // Rays in the unit (one walker with its skid buffer holds up to 3, Slots walkers one
  // each), lines out (up to a record's 3 per walker) and tests out (one per walker); the
  // pipeline's memory-order FIFO and test table hold fewer than 2^10 of each.
  localparam int unsigned CountBits = TuPipe != 0 ? 10 : $clog2(3 * TuSlots + 4);
  logic [CountBits-1:0] rays_in_d, rays_in_q;
  logic [CountBits-1:0] lines_out_d, lines_out_q;
  logic [CountBits-1:0] tests_out_d, tests_out_q;
  logic       ray_in, ray_out, line_out, line_back, test_out, test_back;
  assign ray_in    = req_valid_i && req_ready_o;
  assign ray_out   = rsp_valid_o && rsp_ready_i;
  assign line_out  = mem_req_valid_o && mem_req_ready_i;
  assign line_back = mem_rsp_valid_i && mem_rsp_ready_o;
  assign test_out  = iu_req_valid && iu_req_ready;
  assign test_back = iu_rsp_valid && iu_rsp_ready;
  assign rays_in_d   = rays_in_q + CountBits'(ray_in) - CountBits'(ray_out);
  assign lines_out_d = lines_out_q + CountBits'(line_out) - CountBits'(line_back);
  assign tests_out_d = tests_out_q + CountBits'(test_out) - CountBits'(test_back);

  rpu_clock_gate u_tu_gate (
    .clk_i,
    .en_i(req_valid_i || rays_in_q != '0 || lines_out_q != '0 || tests_out_q != '0),
    .clk_o(tu_clk)
  );

  rpu_pkg::ray_unit_counters_t counters_d, counters_q;
  always_comb begin : count_cycles
    counters_d = counters_q;
    if (count_i) begin
      if (rays_in_q == '0)                           counters_d.idle = counters_q.idle + 32'd1;
      else if (lines_out_q != '0 || mem_req_valid_o) counters_d.wait_memory = counters_q.wait_memory + 32'd1;
      else if (tests_out_q != '0 || iu_req_valid)    counters_d.wait_iu = counters_q.wait_iu + 32'd1;
      else                                           counters_d.busy = counters_q.busy + 32'd1;
      if (ray_out) begin
        counters_d.rays   = counters_q.rays + 32'd1;
        counters_d.nodes  = counters_q.nodes + rsp_o.nodes;
        counters_d.leaves = counters_q.leaves + rsp_o.leaves;
        counters_d.tests  = counters_q.tests + rsp_o.tests;
      end
    end
  end
  assign counters_o = counters_q;

  always_ff @(posedge clk_i or negedge rst_ni) begin : regs
    if (!rst_ni) begin
      rays_in_q   <= '0;
      lines_out_q <= '0;
      tests_out_q <= '0;
      counters_q  <= '0;
    end else begin
      rays_in_q   <= rays_in_d;
      lines_out_q <= lines_out_d;
      tests_out_q <= tests_out_d;
      counters_q  <= counters_d;
    end
  end

endmodule
