// One valid/ready stream to one of Outputs, the one index_i names (the payload goes to
// every output; only that one's valid rises). Combinational. The arbiters send their
// answers back with it, by the requester or cache the answer's tag names.
module rpu_demux #(
  parameter int unsigned Outputs   = 2,
  parameter int unsigned IndexBits = 1
) (
  input  logic                 valid_i,
  output logic                 ready_o,
  input  logic [IndexBits-1:0] index_i,

  output logic [Outputs-1:0]   valid_o,
  input  logic [Outputs-1:0]   ready_i
);

  always_comb begin : route_handshake
    ready_o = 1'b0;
    for (int o = 0; o < Outputs; o++) begin
      valid_o[o] = valid_i && 32'(index_i) == o;
      if (32'(index_i) == o) ready_o = ready_i[o];
    end
  end

endmodule
