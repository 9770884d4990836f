// The traversal unit as the Verilator harness drives it (sim/tu_cosim.cpp), its structs
// flattened into named ports. WithIu = 0: rpu_tu with its IU port open, so the harness
// answers the IU's tests with the C++ intersection unit; WithIu = 1 (tu_cosim --with-iu):
// the ray unit (rpu_tu + rpu_iu), the IU port's pins tied off. Only wiring: a synthesis
// of this top has the unit's cells.
module rpu_tu_cosim_top #(
  parameter int unsigned ExpBits    = rpu_pkg::FormatFp32ExponentBits,
  parameter int unsigned FracBits   = rpu_pkg::FormatFp32FractionBits,
  parameter int unsigned IsectMode  = rpu_pkg::IsectModeWoop,
  parameter int unsigned StackDepth = rpu_pkg::ConfigDefaultStackDepth,
  parameter int unsigned WithIu     = 0
) (
  input  logic          clk_i,
  input  logic          rst_ni,

  input  logic [31:0]   cfg_kd_nodes_i,
  input  logic [31:0]   cfg_prim_refs_i,
  input  logic [31:0]   cfg_isect_records_i,
  input  logic [95:0]   cfg_bounds_lo_i,
  input  logic [95:0]   cfg_bounds_hi_i,
  input  logic [7:0]    cfg_kd_scale_exponent_i,

  input  logic          req_valid_i,
  output logic          req_ready_o,
  input  logic [7:0]    req_tag_i,
  input  logic [95:0]   req_origin_i,
  input  logic [95:0]   req_direction_i,
  input  logic [31:0]   req_t_min_i,
  input  logic [31:0]   req_t_max_i,
  input  logic          req_any_hit_i,

  output logic          rsp_valid_o,
  input  logic          rsp_ready_i,
  output logic [7:0]    rsp_tag_o,
  output logic          rsp_hit_o,
  output logic [31:0]   rsp_t_o,
  output logic [31:0]   rsp_u_o,
  output logic [31:0]   rsp_v_o,
  output logic [31:0]   rsp_prim_o,
  output logic [31:0]   rsp_nodes_o,
  output logic [31:0]   rsp_leaves_o,
  output logic [31:0]   rsp_tests_o,
  output logic          rsp_fault_o,

  output logic          mem_req_valid_o,
  input  logic          mem_req_ready_i,
  output logic [31:0]   mem_req_addr_o,
  input  logic          mem_rsp_valid_i,
  output logic          mem_rsp_ready_o,
  input  logic [127:0]  mem_rsp_data_i,

  output logic          iu_req_valid_o,
  input  logic          iu_req_ready_i,
  output logic [7:0]    iu_req_tag_o,
  output logic [95:0]   iu_req_origin_o,
  output logic [95:0]   iu_req_direction_o,
  output logic [31:0]   iu_req_t_min_o,
  output logic [31:0]   iu_req_t_best_o,
  output logic [5:0]    iu_req_axes_o,      // {kz, ky, kx}
  output logic [63:0]   iu_req_shear_o,     // {y, x}
  output logic [383:0]  iu_req_record_o,
  input  logic          iu_rsp_valid_i,
  output logic          iu_rsp_ready_o,
  input  logic [7:0]    iu_rsp_tag_i,
  input  logic          iu_rsp_hit_i,
  input  logic [31:0]   iu_rsp_t_i,
  input  logic [31:0]   iu_rsp_u_i,
  input  logic [31:0]   iu_rsp_v_i
);

  rpu_pkg::tu_cfg_t  cfg;
  rpu_pkg::tu_req_t  req;
  rpu_pkg::tu_rsp_t  rsp;
  rpu_pkg::mem_req_t mem_req;
  rpu_pkg::mem_rsp_t mem_rsp;
  rpu_pkg::iu_req_t  iu_req;
  rpu_pkg::iu_rsp_t  iu_rsp;

  assign cfg = {cfg_kd_nodes_i, cfg_prim_refs_i, cfg_isect_records_i, cfg_bounds_lo_i, cfg_bounds_hi_i,
                cfg_kd_scale_exponent_i};
  assign req = {req_tag_i, req_origin_i, req_direction_i, req_t_min_i, req_t_max_i, req_any_hit_i};
  assign {rsp_tag_o, rsp_hit_o, rsp_t_o, rsp_u_o, rsp_v_o, rsp_prim_o, rsp_nodes_o, rsp_leaves_o,
          rsp_tests_o, rsp_fault_o} = rsp;
  assign mem_req_addr_o = mem_req.addr;
  assign mem_rsp.data = mem_rsp_data_i;
  assign {iu_req_tag_o, iu_req_origin_o, iu_req_direction_o, iu_req_t_min_o, iu_req_t_best_o,
          iu_req_axes_o[1:0], iu_req_axes_o[3:2], iu_req_axes_o[5:4], iu_req_shear_o[31:0],
          iu_req_shear_o[63:32], iu_req_record_o} = iu_req;
  assign iu_rsp = {iu_rsp_tag_i, iu_rsp_hit_i, iu_rsp_t_i, iu_rsp_u_i, iu_rsp_v_i};

  if (WithIu != 0) begin : g_ray_unit
    rpu_ray_unit #(.ExpBits(ExpBits), .FracBits(FracBits), .IsectMode(IsectMode), .StackDepth(StackDepth))
        u_ray_unit (
      .clk_i, .rst_ni, .cfg_i(cfg),
      .req_valid_i, .req_ready_o, .req_i(req),
      .rsp_valid_o, .rsp_ready_i, .rsp_o(rsp),
      .mem_req_valid_o, .mem_req_ready_i, .mem_req_o(mem_req),
      .mem_rsp_valid_i, .mem_rsp_ready_o, .mem_rsp_i(mem_rsp)
    );
    assign iu_req_valid_o = 1'b0;
    assign iu_req         = '0;
    assign iu_rsp_ready_o = 1'b0;
    logic unused_iu_port;
    assign unused_iu_port = ^{iu_req_ready_i, iu_rsp_valid_i, iu_rsp};
  end else begin : g_tu
    rpu_tu #(.ExpBits(ExpBits), .FracBits(FracBits), .IsectMode(IsectMode), .StackDepth(StackDepth)) u_tu (
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
