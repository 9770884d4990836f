// The intersection unit: ray/triangle tests (docs/traversal.md §4 Woop's unit-triangle
// test, or §5 the watertight test, chosen by IsectMode), bit for bit the operation
// sequence of intersect_woop / intersect_watertight in
// cmodel/functional/intersection_unit.hpp, pipelined: one test accepted every cycle,
// each answered a fixed number of cycles later, in order (docs/rtl.md "Intersection
// unit"; spec/latencies.toml [iu.*] holds the latency the co-simulation measures).
// Every rounded operation has its own operator (rpu_iu_woop, rpu_iu_watertight).
//
// Handshake: stage 0 registers the request; the whole pipeline moves in a cycle in
// which its answer, if any, is taken (or there is none), so an answer not taken holds
// every test behind it and req_ready_o falls.
//
// The pipeline's clock runs only while a test is in it or one is offered
// (rpu_clock_gate): an empty pipeline would only move bubbles.
module rpu_iu #(
  parameter int unsigned ExpBits   = rpu_pkg::FormatFp32ExponentBits,
  parameter int unsigned FracBits  = rpu_pkg::FormatFp32FractionBits,
  parameter int unsigned IsectMode = rpu_pkg::IsectModeWoop
) (
  input  logic             clk_i,
  input  logic             rst_ni,

  input  logic             req_valid_i,
  output logic             req_ready_o,
  input  rpu_pkg::iu_req_t req_i,

  output logic             rsp_valid_o,
  input  logic             rsp_ready_i,
  output rpu_pkg::iu_rsp_t rsp_o
);

  logic             advance, valid_q;
  rpu_pkg::iu_req_t req_q;

  assign advance     = !rsp_valid_o || rsp_ready_i;
  assign req_ready_o = advance;

  // Tests in the unit: taken into stage 0 and not yet answered. Far more than the
  // deepest format's pipeline (spec/latencies.toml [iu]) could hold.
  localparam int unsigned InFlightBits = 7;
  logic [InFlightBits-1:0] in_flight_q, in_flight_d;
  logic                    pipe_clk;

  assign in_flight_d = in_flight_q + InFlightBits'(req_valid_i && advance)
                                   - InFlightBits'(rsp_valid_o && rsp_ready_i);

  always_ff @(posedge clk_i or negedge rst_ni) begin : in_flight_reg
    if (!rst_ni) in_flight_q <= '0;
    else         in_flight_q <= in_flight_d;
  end

  rpu_clock_gate u_pipe_gate (
    .clk_i, .en_i(req_valid_i || in_flight_q != '0), .clk_o(pipe_clk)
  );

  rpu_en_reg #(.Width(1 + $bits(req_i))) u_req (
    .clk_i(pipe_clk), .rst_ni, .en_i(advance), .data_i({req_valid_i, req_i}), .data_o({valid_q, req_q})
  );

  localparam int unsigned W = 1 + ExpBits + FracBits;
  logic                          valid;
  logic [rpu_pkg::RayTagBits-1:0] tag;
  logic                          hit;
  logic [W-1:0]                  t, u, v;

  if (IsectMode == rpu_pkg::IsectModeWatertight) begin : g_watertight
    rpu_iu_watertight #(.ExpBits(ExpBits), .FracBits(FracBits)) u_test (
      .clk_i(pipe_clk), .rst_ni, .en_i(advance), .valid_i(valid_q), .req_i(req_q),
      .valid_o(valid), .tag_o(tag), .hit_o(hit), .t_o(t), .u_o(u), .v_o(v)
    );
  end else begin : g_woop
    rpu_iu_woop #(.ExpBits(ExpBits), .FracBits(FracBits)) u_test (
      .clk_i(pipe_clk), .rst_ni, .en_i(advance), .valid_i(valid_q), .req_i(req_q),
      .valid_o(valid), .tag_o(tag), .hit_o(hit), .t_o(t), .u_o(u), .v_o(v)
    );
  end

  // The answer register; t, u, v are zero on a miss.
  rpu_pkg::iu_rsp_t rsp_d;
  assign rsp_d.tag = tag;
  assign rsp_d.hit = hit;
  assign rsp_d.t   = hit ? 32'(t) : '0;
  assign rsp_d.u   = hit ? 32'(u) : '0;
  assign rsp_d.v   = hit ? 32'(v) : '0;
  rpu_en_reg #(.Width(1 + $bits(rsp_d))) u_rsp (
    .clk_i(pipe_clk), .rst_ni, .en_i(advance), .data_i({valid, rsp_d}), .data_o({rsp_valid_o, rsp_o})
  );

`ifndef SYNTHESIS
  // The count and the pipeline agree: an answer is never out of an empty unit, and the
  // count neither wraps nor goes below zero.
  always_ff @(posedge clk_i) begin : in_flight_checks
    if (rst_ni) begin
      assert (in_flight_q != '0 || !rsp_valid_o)
        else $error("rpu_iu: an answer with no test in flight");
      assert (!(in_flight_q == '1 && req_valid_i && advance && !(rsp_valid_o && rsp_ready_i)))
        else $error("rpu_iu: more tests in flight than the count holds");
    end
  end
`endif

endmodule
