// A synchronous RAM of Depth words of Width bits: one write port, one read port, the
// read data the cycle after its address (a read of the word written in the same cycle
// returns the old word). Written in the form FPGA tools map to block RAM and ASIC flows
// to an SRAM macro, and Yosys keeps as one $mem cell (docs/area.md counts its bits
// apart from the logic). The contents have no reset: a user never reads a word it has
// not written (the shader core's register file keeps a written bit per register).
module rpu_ram #(
  parameter int unsigned Width = 32,
  parameter int unsigned Depth = 16,
  localparam int unsigned AddrBits = Depth > 1 ? $clog2(Depth) : 1
) (
  input  logic                clk_i,

  input  logic                we_i,
  input  logic [AddrBits-1:0] waddr_i,
  input  logic [Width-1:0]    wdata_i,

  input  logic [AddrBits-1:0] raddr_i,
  output logic [Width-1:0]    rdata_o
);

  logic [Width-1:0] mem_q [Depth];
  logic [Width-1:0] rdata_q;

  // The block-RAM template: the array's write and the registered read in one clocked
  // process, which is what the tools recognise (the one exception to _q <= _d).
  always_ff @(posedge clk_i) begin : write_and_read
    if (we_i) mem_q[waddr_i] <= wdata_i;
    rdata_q <= mem_q[raddr_i];
  end

  assign rdata_o = rdata_q;

`ifndef SYNTHESIS
  // An address past Depth (Depth not a power of two) would read or write nothing.
  always_ff @(posedge clk_i) begin : check_write_address
    if (we_i) assert (32'(waddr_i) < Depth) else $error("rpu_ram: write address %0d past depth %0d", waddr_i, Depth);
  end
`endif

endmodule
