// N valid/ready streams of Width bits onto one, round robin: the first valid input
// after the one granted last. A grant that is presented but not taken is held until
// it is taken, so the output's payload does not change while it waits (inputs keep
// their valid until taken, as every valid/ready stream here does). Combinational:
// ready_o follows ready_i, and the output is valid in the cycle an input is. The
// cache and memory arbiters share it (rpu_cache_arbiter, rpu_mem_arbiter).
module rpu_rr_arbiter #(
  parameter int unsigned Inputs = 2,
  parameter int unsigned Width  = 1,
  localparam int unsigned IndexBits = Inputs > 1 ? $clog2(Inputs) : 1
) (
  input  logic                      clk_i,
  input  logic                      rst_ni,

  input  logic [Inputs-1:0]         valid_i,
  output logic [Inputs-1:0]         ready_o,
  input  logic [Inputs*Width-1:0]   data_i,

  output logic                      valid_o,
  input  logic                      ready_i,
  output logic [Width-1:0]          data_o,
  output logic [IndexBits-1:0]      index_o  // the input granted
);

  logic [IndexBits-1:0] last_d, last_q, held_d, held_q;
  logic                 hold_d, hold_q;
  logic [IndexBits-1:0] grant;

  always_comb begin : pick_grant
    valid_o = 1'b0;
    grant   = '0;
    // Inputs last+N down to last+1: the nearest after the last grant wins.
    for (int k = Inputs; k >= 1; k--) begin
      int unsigned i;
      i = 32'(last_q) + 32'(k);
      if (i >= Inputs) i = i - Inputs;
      if (valid_i[i]) begin
        valid_o = 1'b1;
        grant   = IndexBits'(i);
      end
    end
    if (hold_q && valid_i[held_q]) grant = held_q;
  end

  assign index_o = grant;
  assign data_o  = data_i[32'(grant)*Width +: Width];
  for (genvar i = 0; i < Inputs; i++) begin : g_ready
    assign ready_o[i] = ready_i && valid_o && 32'(grant) == i;
  end

  assign last_d = valid_o && ready_i ? grant : last_q;
  assign hold_d = valid_o && !ready_i;
  assign held_d = grant;

  always_ff @(posedge clk_i or negedge rst_ni) begin : regs
    if (!rst_ni) begin
      last_q <= IndexBits'(Inputs - 1);  // input 0 first
      held_q <= '0;
      hold_q <= 1'b0;
    end else begin
      last_q <= last_d;
      held_q <= held_d;
      hold_q <= hold_d;
    end
  end

`ifndef SYNTHESIS
  // A valid input keeps its payload until it is taken.
  logic [Inputs-1:0]       stalled_q;
  logic [Inputs*Width-1:0] stalled_data_q;
  always_ff @(posedge clk_i or negedge rst_ni) begin : check_inputs_held
    if (!rst_ni) begin
      stalled_q <= '0;
      stalled_data_q <= '0;
    end else begin
      for (int i = 0; i < Inputs; i++) begin
        if (stalled_q[i]) begin
          assert (valid_i[i] && data_i[i*Width +: Width] == stalled_data_q[i*Width +: Width])
            else $error("rpu_rr_arbiter: input %0d dropped or changed a request before it was taken", i);
        end
      end
      stalled_q <= valid_i & ~ready_o;
      stalled_data_q <= data_i;
    end
  end
`endif

endmodule
