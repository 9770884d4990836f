// One pipeline stage of a valid/ready stream: a register that accepts new data when
// it is empty or its content leaves in the same cycle, so a chain of them runs at one
// transfer per cycle and stalls from the output backwards (ready_o is combinational
// from ready_i). Shared by every pipelined unit instead of per-unit handshake logic.
module rpu_pipe_reg #(
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

  logic             valid_d, valid_q;
  logic [Width-1:0] data_d, data_q;

  assign ready_o = ~valid_q | ready_i;

  always_comb begin : load_stage
    valid_d = ready_o ? valid_i : valid_q;
    data_d  = (valid_i && ready_o) ? data_i : data_q;
  end

  always_ff @(posedge clk_i or negedge rst_ni) begin : regs
    if (!rst_ni) begin
      valid_q <= 1'b0;
      data_q  <= '0;
    end else begin
      valid_q <= valid_d;
      data_q  <= data_d;
    end
  end

  assign valid_o = valid_q;
  assign data_o  = data_q;

endmodule
