// The top that the IU harness (sim/iu_cosim.cpp) and the netlist simulation drive:
// rpu_iu with its request and response structs flattened into plain ports, so the C++
// harness and the netlist testbench set fields by name, not by bit offset. Vectors of
// 32-bit words keep word k at bits [32k +: 32] (rpu_pkg). Only wiring: a synthesis of
// this top has the unit's cells.
module rpu_iu_cosim_top #(
  parameter int unsigned ExpBits   = rpu_pkg::FormatFp32ExponentBits,
  parameter int unsigned FracBits  = rpu_pkg::FormatFp32FractionBits,
  parameter int unsigned IsectMode = rpu_pkg::IsectModeWoop
) (
  input  logic                                     clk_i,
  input  logic                                     rst_ni,

  input  logic                                     req_valid_i,
  output logic                                     req_ready_o,
  input  logic [rpu_pkg::RayTagBits-1:0]           req_tag_i,
  input  logic [3*32-1:0]                          req_origin_i,
  input  logic [3*32-1:0]                          req_direction_i,
  input  logic [31:0]                              req_t_min_i,
  input  logic [31:0]                              req_t_best_i,
  input  logic [1:0]                               req_kx_i,
  input  logic [1:0]                               req_ky_i,
  input  logic [1:0]                               req_kz_i,
  input  logic [31:0]                              req_shear_x_i,
  input  logic [31:0]                              req_shear_y_i,
  input  logic [rpu_pkg::IsectRecordWords*32-1:0]  req_record_i,

  output logic                                     rsp_valid_o,
  input  logic                                     rsp_ready_i,
  output logic [rpu_pkg::RayTagBits-1:0]           rsp_tag_o,
  output logic                                     rsp_hit_o,
  output logic [31:0]                              rsp_t_o,
  output logic [31:0]                              rsp_u_o,
  output logic [31:0]                              rsp_v_o
);

  rpu_pkg::iu_req_t req;
  rpu_pkg::iu_rsp_t rsp;

  assign req = {req_tag_i, req_origin_i, req_direction_i, req_t_min_i, req_t_best_i, req_kx_i, req_ky_i,
                req_kz_i, req_shear_x_i, req_shear_y_i, req_record_i};
  assign rsp_tag_o = rsp.tag;
  assign rsp_hit_o = rsp.hit;
  assign rsp_t_o   = rsp.t;
  assign rsp_u_o   = rsp.u;
  assign rsp_v_o   = rsp.v;

  rpu_iu #(.ExpBits(ExpBits), .FracBits(FracBits), .IsectMode(IsectMode)) u_iu (
    .clk_i, .rst_ni, .req_valid_i, .req_ready_o, .req_i(req),
    .rsp_valid_o, .rsp_ready_i, .rsp_o(rsp)
  );

endmodule
