// A register that loads data_i in the cycles en_i is high: a stage of a pipeline that
// stalls as a whole (rpu_iu's datapaths, rpu_fp_div_pipe), where rpu_pipe_reg's
// per-stage handshake is not needed. Cycles > 1 chains that many (a delay line).
module rpu_en_reg #(
  parameter int unsigned Width  = 1,
  parameter int unsigned Cycles = 1
) (
  input  logic             clk_i,
  input  logic             rst_ni,
  input  logic             en_i,
  input  logic [Width-1:0] data_i,
  output logic [Width-1:0] data_o
);

  logic [Cycles*Width-1:0] q_d, q_q;  // the value k+1 cycles old in bits [k*Width +: Width]

  if (Cycles == 1) begin : g_one
    assign q_d = data_i;
  end else begin : g_chain
    assign q_d = {q_q[(Cycles-1)*Width-1:0], data_i};
  end

  always_ff @(posedge clk_i or negedge rst_ni) begin : regs
    if (!rst_ni) q_q <= '0;
    else if (en_i) q_q <= q_d;
  end

  assign data_o = q_q[(Cycles-1)*Width +: Width];

`ifndef SYNTHESIS
  initial assert (Cycles >= 1) else $error("rpu_en_reg: Cycles must be at least 1");
`endif

endmodule
