// The watertight test (docs/traversal.md §5) as a pipeline: every rounded operation of
// intersect_watertight (cmodel/functional/intersection_unit.hpp) has its own operator,
// one stage each, in the C++ order, so a test is accepted every cycle and answered a
// fixed number of cycles later. Stage by stage (the request is stage 0):
//   1  the record's vertices A, B, C and the normal n into the format
//   2  P_k = V_k - O (the vertices relative to the origin);  n_i * D_i
//   3  S_x P_k[kz], S_y P_k[kz];  n_i * P_0i;  n_x D_x + n_y D_y
//   4  x_k = P_k[kx] - S_x P_k[kz], y_k likewise;  partial n.P_0;  n.D
//   5  the edge functions' six products;  n.P_0
//   6  U, V, W
//   7  U + V;  the edge signs
//   8  det = (U + V) + W;  edges of one sign
//   9  t = n.P_0 / n.D, u = V / det, v = W / det on three rpu_fp_div_pipe (their
//      stages), with what the answer needs riding alongside t
//   +1 the answer: t > t_min, t < t_best, det nonzero and the edges decide
// The whole pipeline moves when en_i is high.
module rpu_iu_watertight #(
  parameter int unsigned ExpBits  = rpu_pkg::FormatFp32ExponentBits,
  parameter int unsigned FracBits = rpu_pkg::FormatFp32FractionBits
) (
  input  logic             clk_i,
  input  logic             rst_ni,
  input  logic             en_i,

  input  logic             valid_i,
  input  rpu_pkg::iu_req_t req_i,

  // The last stage's answer, combinational (rpu_iu registers it).
  output logic                          valid_o,
  output logic [rpu_pkg::RayTagBits-1:0] tag_o,
  output logic                          hit_o,
  output logic [ExpBits+FracBits:0]     t_o,
  output logic [ExpBits+FracBits:0]     u_o,
  output logic [ExpBits+FracBits:0]     v_o
);

  localparam int unsigned W = 1 + ExpBits + FracBits;
  localparam int unsigned TagBits = rpu_pkg::RayTagBits;
  localparam int unsigned Row0 = rpu_pkg::TriangleRecordRow0At / 4;
  localparam int unsigned Row1 = rpu_pkg::TriangleRecordRow1At / 4;
  localparam int unsigned Row2 = rpu_pkg::TriangleRecordRow2At / 4;

  function automatic logic [31:0] ext(input logic [W-1:0] x);
    ext = 32'(x);
  endfunction

  // What passes beside the arithmetic to the division: valid, tag, t_min, t_best.
  localparam int unsigned CtlBits = 1 + TagBits + 2 * W;
  logic [CtlBits-1:0] ctl8;
  rpu_en_reg #(.Width(CtlBits), .Cycles(8)) u_ctl (
    .clk_i, .rst_ni, .en_i, .data_i({valid_i, req_i.tag, req_i.t_min[W-1:0], req_i.t_best[W-1:0]}), .data_o(ctl8)
  );

  // Stage 1: vertex k's coordinate i at v1[(3k + i)W], the normal's at n1[iW] (vertex
  // i's w word); the ray a stage on. Stage 2: P_k = V_k - O; n_i D_i.
  logic [9*W-1:0] v1, p2;
  logic [3*W-1:0] n1, n2, o1, d1, nd2;
  logic [W-1:0]   sx2, sy2;
  logic [1:0]     kx2, ky2;
  for (genvar k = 0; k < 3; k++) begin : g_vertex
    localparam int unsigned At = k == 0 ? Row0 : k == 1 ? Row1 : Row2;
    for (genvar i = 0; i < 3; i++) begin : g_coord
      rpu_fp_pipe_op #(.ExpBits(ExpBits), .FracBits(FracBits), .Op(rpu_pkg::FpOpFromFp32)) u_load (
        .clk_i, .rst_ni, .en_i, .a_i(req_i.record[(At + i)*32 +: 32]), .b_i('0), .result_o(v1[(3*k + i)*W +: W])
      );
      rpu_fp_pipe_op #(.ExpBits(ExpBits), .FracBits(FracBits), .Op(rpu_pkg::FpOpSub)) u_p (
        .clk_i, .rst_ni, .en_i, .a_i(ext(v1[(3*k + i)*W +: W])), .b_i(ext(o1[i*W +: W])),
        .result_o(p2[(3*k + i)*W +: W])
      );
    end
    rpu_fp_pipe_op #(.ExpBits(ExpBits), .FracBits(FracBits), .Op(rpu_pkg::FpOpFromFp32)) u_normal (
      .clk_i, .rst_ni, .en_i, .a_i(req_i.record[(At + 3)*32 +: 32]), .b_i('0), .result_o(n1[k*W +: W])
    );
  end
  for (genvar i = 0; i < 3; i++) begin : g_ray
    rpu_en_reg #(.Width(2 * W)) u_ray (
      .clk_i, .rst_ni, .en_i, .data_i({req_i.origin[i*32 +: W], req_i.direction[i*32 +: W]}),
      .data_o({o1[i*W +: W], d1[i*W +: W]})
    );
    rpu_fp_pipe_op #(.ExpBits(ExpBits), .FracBits(FracBits), .Op(rpu_pkg::FpOpMul)) u_nd (
      .clk_i, .rst_ni, .en_i, .a_i(ext(n1[i*W +: W])), .b_i(ext(d1[i*W +: W])), .result_o(nd2[i*W +: W])
    );
  end
  rpu_en_reg #(.Width(3 * W)) u_n2 (.clk_i, .rst_ni, .en_i, .data_i(n1), .data_o(n2));
  rpu_en_reg #(.Width(2 * W + 4), .Cycles(2)) u_shear (
    .clk_i, .rst_ni, .en_i, .data_i({req_i.shear_x[W-1:0], req_i.shear_y[W-1:0], req_i.kx, req_i.ky}),
    .data_o({sx2, sy2, kx2, ky2})
  );

  // Stage 3: S_x P_k[kz], S_y P_k[kz]; n_i P_0i; n_x D_x + n_y D_y. kz is the axis
  // neither kx nor ky names.
  logic [3*W-1:0] zx3, zy3, pkx3, pky3, na3;
  logic [W-1:0]   nd01_3, nd2_3;
  for (genvar k = 0; k < 3; k++) begin : g_shear
    logic [W-1:0] px, py, pz, c0, c1, c2;
    assign {c2, c1, c0} = p2[3*k*W +: 3*W];
    assign px = kx2 == 2'd0 ? c0 : kx2 == 2'd1 ? c1 : c2;
    assign py = ky2 == 2'd0 ? c0 : ky2 == 2'd1 ? c1 : c2;
    assign pz = kx2 != 2'd0 && ky2 != 2'd0 ? c0 : kx2 != 2'd1 && ky2 != 2'd1 ? c1 : c2;
    rpu_fp_pipe_op #(.ExpBits(ExpBits), .FracBits(FracBits), .Op(rpu_pkg::FpOpMul)) u_zx (
      .clk_i, .rst_ni, .en_i, .a_i(ext(sx2)), .b_i(ext(pz)), .result_o(zx3[k*W +: W])
    );
    rpu_fp_pipe_op #(.ExpBits(ExpBits), .FracBits(FracBits), .Op(rpu_pkg::FpOpMul)) u_zy (
      .clk_i, .rst_ni, .en_i, .a_i(ext(sy2)), .b_i(ext(pz)), .result_o(zy3[k*W +: W])
    );
    rpu_en_reg #(.Width(2 * W)) u_pxy (.clk_i, .rst_ni, .en_i, .data_i({px, py}), .data_o({pkx3[k*W +: W], pky3[k*W +: W]}));
    rpu_fp_pipe_op #(.ExpBits(ExpBits), .FracBits(FracBits), .Op(rpu_pkg::FpOpMul)) u_na (
      .clk_i, .rst_ni, .en_i, .a_i(ext(n2[k*W +: W])), .b_i(ext(p2[k*W +: W])), .result_o(na3[k*W +: W])
    );
  end
  rpu_fp_pipe_op #(.ExpBits(ExpBits), .FracBits(FracBits), .Op(rpu_pkg::FpOpAdd)) u_nd01 (
    .clk_i, .rst_ni, .en_i, .a_i(ext(nd2[0 +: W])), .b_i(ext(nd2[W +: W])), .result_o(nd01_3)
  );
  rpu_en_reg #(.Width(W)) u_nd2 (.clk_i, .rst_ni, .en_i, .data_i(nd2[2*W +: W]), .data_o(nd2_3));

  // Stage 4: x_k, y_k; n_x P_0x + n_y P_0y; n.D.
  logic [3*W-1:0] x4, y4;
  logic [W-1:0]   na01_4, na2_4, nd4;
  for (genvar k = 0; k < 3; k++) begin : g_xy
    rpu_fp_pipe_op #(.ExpBits(ExpBits), .FracBits(FracBits), .Op(rpu_pkg::FpOpSub)) u_x (
      .clk_i, .rst_ni, .en_i, .a_i(ext(pkx3[k*W +: W])), .b_i(ext(zx3[k*W +: W])), .result_o(x4[k*W +: W])
    );
    rpu_fp_pipe_op #(.ExpBits(ExpBits), .FracBits(FracBits), .Op(rpu_pkg::FpOpSub)) u_y (
      .clk_i, .rst_ni, .en_i, .a_i(ext(pky3[k*W +: W])), .b_i(ext(zy3[k*W +: W])), .result_o(y4[k*W +: W])
    );
  end
  rpu_fp_pipe_op #(.ExpBits(ExpBits), .FracBits(FracBits), .Op(rpu_pkg::FpOpAdd)) u_na01 (
    .clk_i, .rst_ni, .en_i, .a_i(ext(na3[0 +: W])), .b_i(ext(na3[W +: W])), .result_o(na01_4)
  );
  rpu_en_reg #(.Width(W)) u_na2 (.clk_i, .rst_ni, .en_i, .data_i(na3[2*W +: W]), .data_o(na2_4));
  rpu_fp_pipe_op #(.ExpBits(ExpBits), .FracBits(FracBits), .Op(rpu_pkg::FpOpAdd)) u_nd (
    .clk_i, .rst_ni, .en_i, .a_i(ext(nd01_3)), .b_i(ext(nd2_3)), .result_o(nd4)
  );

  // Stage 5: the edge functions' products, U = x2 y1 - y2 x1 (edge BC), V = x0 y2 -
  // y0 x2 (CA), W = x1 y0 - y1 x0 (AB); n.P_0.
  logic [6*W-1:0] e5;
  logic [W-1:0]   na5, nd5;
  for (genvar j = 0; j < 3; j++) begin : g_edge
    localparam int unsigned Ka = (j + 2) % 3;  // U: x2 y1 - y2 x1
    localparam int unsigned Kb = (j + 1) % 3;
    rpu_fp_pipe_op #(.ExpBits(ExpBits), .FracBits(FracBits), .Op(rpu_pkg::FpOpMul)) u_left (
      .clk_i, .rst_ni, .en_i, .a_i(ext(x4[Ka*W +: W])), .b_i(ext(y4[Kb*W +: W])), .result_o(e5[2*j*W +: W])
    );
    rpu_fp_pipe_op #(.ExpBits(ExpBits), .FracBits(FracBits), .Op(rpu_pkg::FpOpMul)) u_right (
      .clk_i, .rst_ni, .en_i, .a_i(ext(y4[Ka*W +: W])), .b_i(ext(x4[Kb*W +: W])), .result_o(e5[(2*j + 1)*W +: W])
    );
  end
  rpu_fp_pipe_op #(.ExpBits(ExpBits), .FracBits(FracBits), .Op(rpu_pkg::FpOpAdd)) u_na (
    .clk_i, .rst_ni, .en_i, .a_i(ext(na01_4)), .b_i(ext(na2_4)), .result_o(na5)
  );
  rpu_en_reg #(.Width(W)) u_nd5 (.clk_i, .rst_ni, .en_i, .data_i(nd4), .data_o(nd5));

  // Stage 6: U, V, W. Stage 7: U + V and the edge signs. Stage 8: det, one sign.
  logic [3*W-1:0] uvw6;
  logic [W-1:0]   uv7, w7, v7, det8, w8, v8;
  logic [2*W-1:0] plane6, plane7, plane8;  // n.P_0, n.D
  for (genvar j = 0; j < 3; j++) begin : g_uvw
    rpu_fp_pipe_op #(.ExpBits(ExpBits), .FracBits(FracBits), .Op(rpu_pkg::FpOpSub)) u_e (
      .clk_i, .rst_ni, .en_i, .a_i(ext(e5[2*j*W +: W])), .b_i(ext(e5[(2*j + 1)*W +: W])), .result_o(uvw6[j*W +: W])
    );
  end
  rpu_en_reg #(.Width(2 * W)) u_plane6 (.clk_i, .rst_ni, .en_i, .data_i({na5, nd5}), .data_o(plane6));

  logic [3*W-1:0] neg7, pos7;  // the edge function j below, above zero in bit jW
  for (genvar j = 0; j < 3; j++) begin : g_sign
    rpu_fp_pipe_op #(.ExpBits(ExpBits), .FracBits(FracBits), .Op(rpu_pkg::FpOpLt)) u_neg (
      .clk_i, .rst_ni, .en_i, .a_i(ext(uvw6[j*W +: W])), .b_i('0), .result_o(neg7[j*W +: W])
    );
    rpu_fp_pipe_op #(.ExpBits(ExpBits), .FracBits(FracBits), .Op(rpu_pkg::FpOpGt)) u_pos (
      .clk_i, .rst_ni, .en_i, .a_i(ext(uvw6[j*W +: W])), .b_i('0), .result_o(pos7[j*W +: W])
    );
  end
  rpu_fp_pipe_op #(.ExpBits(ExpBits), .FracBits(FracBits), .Op(rpu_pkg::FpOpAdd)) u_uv (
    .clk_i, .rst_ni, .en_i, .a_i(ext(uvw6[0 +: W])), .b_i(ext(uvw6[W +: W])), .result_o(uv7)
  );
  rpu_en_reg #(.Width(4 * W)) u_s7 (
    .clk_i, .rst_ni, .en_i, .data_i({uvw6[W +: W], uvw6[2*W +: W], plane6}), .data_o({v7, w7, plane7})
  );

  // Reject when the edge functions have both signs.
  logic edges_agree8;
  rpu_fp_pipe_op #(.ExpBits(ExpBits), .FracBits(FracBits), .Op(rpu_pkg::FpOpAdd)) u_det (
    .clk_i, .rst_ni, .en_i, .a_i(ext(uv7)), .b_i(ext(w7)), .result_o(det8)
  );
  rpu_en_reg #(.Width(4 * W + 1)) u_s8 (
    .clk_i, .rst_ni, .en_i,
    .data_i({v7, w7, plane7, !((neg7[0] || neg7[W] || neg7[2*W]) && (pos7[0] || pos7[W] || pos7[2*W]))}),
    .data_o({v8, w8, plane8, edges_agree8})
  );

  // det must be nonzero and not NaN.
  logic [31:0] det_neg, det_pos;
  rpu_fp_misc_core #(.ExpBits(ExpBits), .FracBits(FracBits)) u_det_neg (
    .op_i(rpu_pkg::FpOpLt), .a_i(ext(det8)), .b_i('0), .result_o(det_neg)
  );
  rpu_fp_misc_core #(.ExpBits(ExpBits), .FracBits(FracBits)) u_det_pos (
    .op_i(rpu_pkg::FpOpGt), .a_i(ext(det8)), .b_i('0), .result_o(det_pos)
  );

  // The divisions: t with the rest beside it, u and v.
  localparam int unsigned SideBits = CtlBits + 1;
  logic [W-1:0]       t, u, v;
  logic [CtlBits-1:0] ctlq;
  logic               decided;  // edges of one sign and det nonzero
  logic               u_side_unused, v_side_unused;
  rpu_fp_div_pipe #(.ExpBits(ExpBits), .FracBits(FracBits), .SideBits(SideBits)) u_div_t (
    .clk_i, .rst_ni, .en_i, .a_i(plane8[W +: W]), .b_i(plane8[0 +: W]),
    .side_i({ctl8, edges_agree8 && (det_neg[0] || det_pos[0])}), .quotient_o(t), .side_o({ctlq, decided})
  );
  rpu_fp_div_pipe #(.ExpBits(ExpBits), .FracBits(FracBits)) u_div_u (
    .clk_i, .rst_ni, .en_i, .a_i(v8), .b_i(det8), .side_i(1'b0), .quotient_o(u), .side_o(u_side_unused)
  );
  rpu_fp_div_pipe #(.ExpBits(ExpBits), .FracBits(FracBits)) u_div_v (
    .clk_i, .rst_ni, .en_i, .a_i(w8), .b_i(det8), .side_i(1'b0), .quotient_o(v), .side_o(v_side_unused)
  );

  // The answer: t within (t_min, t_best).
  logic               valid_q;
  logic [TagBits-1:0] tag_q;
  logic [W-1:0]       t_min_q, t_best_q;
  assign {valid_q, tag_q, t_min_q, t_best_q} = ctlq;
  logic [31:0] gt_min, lt_best;
  rpu_fp_misc_core #(.ExpBits(ExpBits), .FracBits(FracBits)) u_gt_min (
    .op_i(rpu_pkg::FpOpGt), .a_i(ext(t)), .b_i(ext(t_min_q)), .result_o(gt_min)
  );
  rpu_fp_misc_core #(.ExpBits(ExpBits), .FracBits(FracBits)) u_lt_best (
    .op_i(rpu_pkg::FpOpLt), .a_i(ext(t)), .b_i(ext(t_best_q)), .result_o(lt_best)
  );
  assign hit_o = decided && gt_min[0] && lt_best[0];

  assign valid_o = valid_q;
  assign tag_o   = tag_q;
  assign t_o     = t;
  assign u_o     = u;
  assign v_o     = v;

  // kz is the axis neither kx nor ky names; compares answer in bit 0; words above the
  // format's width carry nothing.
  logic unused;
  assign unused = ^{req_i.kz, u_side_unused, v_side_unused, det_neg[31:1], det_pos[31:1], gt_min[31:1],
                    lt_best[31:1], neg7[3*W-1:2*W+1], neg7[2*W-1:W+1], neg7[W-1:1],
                    pos7[3*W-1:2*W+1], pos7[2*W-1:W+1], pos7[W-1:1]};
  if (W < 32) begin : g_unused_high
    logic unused_high;
    assign unused_high = ^{req_i.origin[95:64+W], req_i.origin[63:32+W], req_i.origin[31:W],
                           req_i.direction[95:64+W], req_i.direction[63:32+W], req_i.direction[31:W],
                           req_i.t_min[31:W], req_i.t_best[31:W], req_i.shear_x[31:W], req_i.shear_y[31:W]};
  end

endmodule
