// A traversal unit with its intersection unit: what a `trace` instruction hands a ray
// to. rpu_tu walks the kd tree over the memory port and sends each leaf triangle to
// rpu_iu; the ray's hit record comes back on the response port (docs/rtl.md, "Ray
// unit"). Only wiring: both units are the ones co-simulated alone.
module rpu_ray_unit #(
  parameter int unsigned ExpBits    = rpu_pkg::FormatFp32ExponentBits,
  parameter int unsigned FracBits   = rpu_pkg::FormatFp32FractionBits,
  parameter int unsigned IsectMode  = rpu_pkg::IsectModeWoop,
  parameter int unsigned StackDepth = rpu_pkg::ConfigDefaultStackDepth
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
  input  rpu_pkg::mem_rsp_t mem_rsp_i
);

  logic             iu_req_valid, iu_req_ready;
  rpu_pkg::iu_req_t iu_req;
  logic             iu_rsp_valid, iu_rsp_ready;
  rpu_pkg::iu_rsp_t iu_rsp;

  rpu_tu #(.ExpBits(ExpBits), .FracBits(FracBits), .IsectMode(IsectMode), .StackDepth(StackDepth)) u_tu (
    .clk_i, .rst_ni, .cfg_i,
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

endmodule
