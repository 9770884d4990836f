// A skid buffer: cuts the combinational ready path of a valid/ready stream (ready_o is
// a register, unlike rpu_pipe_reg's) at full throughput. While the output stalls, the
// one transfer that ready_o still allowed lands in the skid register; the output takes
// it before new input.
module rpu_skid_buf #(
  parameter int unsigned Width = 1
) (
  input  logic             clk_i,
  input  logic             rst_ni,

  input  logic             valid_i,
  output logic             ready_o,
  input  logic [Width-1:0] data_i,

  output logic             valid_o,
  input  logic             ready_i,
  output logic [Width-1:0] data_o
);

  logic             out_valid_d, out_valid_q, skid_valid_d, skid_valid_q;
  logic [Width-1:0] out_data_d, out_data_q, skid_data_d, skid_data_q;
  logic             push, pop;

  assign ready_o = ~skid_valid_q;
  assign valid_o = out_valid_q;
  assign data_o  = out_data_q;
  assign push = valid_i && ready_o;
  assign pop  = out_valid_q && ready_i;

  always_comb begin : refill_or_skid
    out_valid_d  = out_valid_q;
    out_data_d   = out_data_q;
    skid_valid_d = skid_valid_q;
    skid_data_d  = skid_data_q;
    if (pop || !out_valid_q) begin
      // The output register is free: refill it from the skid register, else the input.
      out_valid_d  = skid_valid_q || push;
      out_data_d   = skid_valid_q ? skid_data_q : data_i;
      skid_valid_d = skid_valid_q && push;
      skid_data_d  = data_i;
    end else if (push) begin
      skid_valid_d = 1'b1;
      skid_data_d  = data_i;
    end
  end

  always_ff @(posedge clk_i or negedge rst_ni) begin : regs
    if (!rst_ni) begin
      out_valid_q  <= 1'b0;
      out_data_q   <= '0;
      skid_valid_q <= 1'b0;
      skid_data_q  <= '0;
    end else begin
      out_valid_q  <= out_valid_d;
      out_data_q   <= out_data_d;
      skid_valid_q <= skid_valid_d;
      skid_data_q  <= skid_data_d;
    end
  end

endmodule
