// The traversal unit as the Verilator harness drives it (sim/tu_cosim.cpp), each stream
// one flat port of its rpu_pkg width (spec/streams.toml), which the harness fills from
// rpu::streams words. WithIu = 0: rpu_tu with its IU port open, so the harness
// answers the IU's tests with the C++ intersection unit; WithIu = 1 (tu_cosim --with-iu):
// the ray unit (rpu_tu + rpu_iu), the IU port's pins tied off. Slots: the TU's ray
// slots (rpu_tu_slots); Pipe = 1: the slots share a node-step pipeline and Setups set-up
// engines (rpu_tu_pipe), alone or in the ray unit. Only wiring: a synthesis of this top
// has the unit's cells.
module rpu_tu_cosim_top #(
  parameter int unsigned ExpBits    = rpu_pkg::FormatFp32ExponentBits,
  parameter int unsigned FracBits   = rpu_pkg::FormatFp32FractionBits,
  parameter int unsigned IsectMode  = rpu_pkg::IsectModeWoop,
  parameter int unsigned StackDepth = rpu_pkg::ConfigDefaultStackDepth,
  parameter int unsigned WithIu     = 0,
  parameter int unsigned Slots      = 1,
  parameter int unsigned Pipe       = 0,
  parameter int unsigned Setups     = 2
) (
  input  logic                            clk_i,
  input  logic                            rst_ni,

  input  logic [rpu_pkg::TuCfgBits-1:0]   cfg_i,

  input  logic                            req_valid_i,
  output logic                            req_ready_o,
  input  logic [rpu_pkg::TuReqBits-1:0]   req_i,

  output logic                            rsp_valid_o,
  input  logic                            rsp_ready_i,
  output logic [rpu_pkg::TuRspBits-1:0]   rsp_o,

  output logic                            mem_req_valid_o,
  input  logic                            mem_req_ready_i,
  output logic [rpu_pkg::MemReqBits-1:0]  mem_req_o,
  input  logic                            mem_rsp_valid_i,
  output logic                            mem_rsp_ready_o,
  input  logic [rpu_pkg::MemRspBits-1:0]  mem_rsp_i,

  output logic                            iu_req_valid_o,
  input  logic                            iu_req_ready_i,
  output logic [rpu_pkg::IuReqBits-1:0]   iu_req_o,
  input  logic                            iu_rsp_valid_i,
  output logic                            iu_rsp_ready_o,
  input  logic [rpu_pkg::IuRspBits-1:0]   iu_rsp_i
);

  rpu_pkg::tu_cfg_t  cfg;
  rpu_pkg::tu_req_t  req;
  rpu_pkg::tu_rsp_t  rsp;
  rpu_pkg::mem_req_t mem_req;
  rpu_pkg::mem_rsp_t mem_rsp;
  rpu_pkg::iu_req_t  iu_req;
  rpu_pkg::iu_rsp_t  iu_rsp;

  assign cfg       = cfg_i;
  assign req       = req_i;
  assign rsp_o     = rsp;
  assign mem_req_o = mem_req;
  assign mem_rsp   = mem_rsp_i;
  assign iu_req_o  = iu_req;
  assign iu_rsp    = iu_rsp_i;

  if (WithIu != 0) begin : g_ray_unit
    // The counters are the chip's (sim/chip_cosim reads them).
    rpu_pkg::ray_unit_counters_t counters;
    rpu_ray_unit #(.ExpBits(ExpBits), .FracBits(FracBits), .IsectMode(IsectMode), .StackDepth(StackDepth),
                   .TuSlots(Slots), .TuPipe(Pipe), .TuSetups(Setups)) u_ray_unit (
      .clk_i, .rst_ni, .cfg_i(cfg),
      .req_valid_i, .req_ready_o, .req_i(req),
      .rsp_valid_o, .rsp_ready_i, .rsp_o(rsp),
      .mem_req_valid_o, .mem_req_ready_i, .mem_req_o(mem_req),
      .mem_rsp_valid_i, .mem_rsp_ready_o, .mem_rsp_i(mem_rsp),
      .count_i(1'b1), .counters_o(counters)
    );
    logic unused_counters;
    assign unused_counters = ^counters;
    assign iu_req_valid_o = 1'b0;
    assign iu_req         = '0;
    assign iu_rsp_ready_o = 1'b0;
    logic unused_iu_port;
    assign unused_iu_port = ^{iu_req_ready_i, iu_rsp_valid_i, iu_rsp};
  end else begin : g_tu
    rpu_tu_slots #(.ExpBits(ExpBits), .FracBits(FracBits), .IsectMode(IsectMode), .StackDepth(StackDepth),
                   .Slots(Slots), .Pipe(Pipe), .Setups(Setups)) u_tu (
      .clk_i, .rst_ni, .cfg_i(cfg),
      .req_valid_i, .req_ready_o, .req_i(req),
      .rsp_valid_o, .rsp_ready_i, .rsp_o(rsp),
      .mem_req_valid_o, .mem_req_ready_i, .mem_req_o(mem_req),
      .mem_rsp_valid_i, .mem_rsp_ready_o, .mem_rsp_i(mem_rsp),
      .iu_req_valid_o, .iu_req_ready_i, .iu_req_o(iu_req),
      .iu_rsp_valid_i, .iu_rsp_ready_o, .iu_rsp_i(iu_rsp)
    );
  end

endmodule
