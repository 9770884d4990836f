// A synchronous valid/ready FIFO of Depth entries of Width bits. The output is the
// oldest entry (first-word fall-through: valid_o the cycle after a write into an empty
// FIFO); in_ready_o is high while an entry is free, so a full FIFO takes a new entry
// only after one leaves. Storage is one flat vector (Yosys 0.23 mis-reads arrays of
// packed structs, docs/style.md "What Yosys 0.23 reads"); callers pack their structs
// into Width bits.
module rpu_fifo #(
  parameter int unsigned Width = 1,
  parameter int unsigned Depth = 2
) (
  input  logic             clk_i,
  input  logic             rst_ni,

  input  logic             in_valid_i,
  output logic             in_ready_o,
  input  logic [Width-1:0] in_data_i,

  output logic             out_valid_o,
  input  logic             out_ready_i,
  output logic [Width-1:0] out_data_o
);

  localparam int unsigned PtrBits = Depth > 1 ? $clog2(Depth) : 1;
  localparam int unsigned CountBits = $clog2(Depth + 1);
  localparam logic [PtrBits-1:0] LastSlot = PtrBits'(Depth - 1);

  logic [Depth*Width-1:0] data_d, data_q;
  logic [PtrBits-1:0]     rd_d, rd_q, wr_d, wr_q;
  logic [CountBits-1:0]   count_d, count_q;
  logic                   push, pop;

  assign in_ready_o  = count_q != CountBits'(Depth);
  assign out_valid_o = count_q != '0;
  assign out_data_o  = data_q[rd_q*Width +: Width];
  assign push = in_valid_i && in_ready_o;
  assign pop  = out_valid_o && out_ready_i;

  always_comb begin : push_pop
    data_d  = data_q;
    rd_d    = rd_q;
    wr_d    = wr_q;
    count_d = count_q;
    if (push) begin
      data_d[wr_q*Width +: Width] = in_data_i;
      wr_d = wr_q == LastSlot ? '0 : wr_q + PtrBits'(1);
    end
    if (pop) begin
      rd_d = rd_q == LastSlot ? '0 : rd_q + PtrBits'(1);
    end
    if (push && !pop) begin
      count_d = count_q + CountBits'(1);
    end else if (pop && !push) begin
      count_d = count_q - CountBits'(1);
    end
  end

  always_ff @(posedge clk_i or negedge rst_ni) begin : regs
    if (!rst_ni) begin
      data_q  <= '0;
      rd_q    <= '0;
      wr_q    <= '0;
      count_q <= '0;
    end else begin
      data_q  <= data_d;
      rd_q    <= rd_d;
      wr_q    <= wr_d;
      count_q <= count_d;
    end
  end

endmodule
