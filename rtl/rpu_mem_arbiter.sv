// The caches' memory ports onto the chip's one memory port, round robin
// (rpu_rr_arbiter). Port c serves the cache whose CacheId is c: its tags already name
// it in their high bits (above DramMshrBits), by which the line reads' answers go back.
// A cache's requests pass one at a time in the order it presents them, so the order
// each cache keeps (fills and writes in program order) holds at the memory port.
module rpu_mem_arbiter #(
  parameter int unsigned Caches = 3
) (
  input  logic                                     clk_i,
  input  logic                                     rst_ni,

  input  logic [Caches-1:0]                        req_valid_i,
  output logic [Caches-1:0]                        req_ready_o,
  input  logic [Caches*rpu_pkg::DramReqBits-1:0]   req_i,        // cache c's at [c*DramReqBits +: DramReqBits]
  output logic [Caches-1:0]                        rsp_valid_o,
  input  logic [Caches-1:0]                        rsp_ready_i,
  output logic [Caches*rpu_pkg::DramRspBits-1:0]   rsp_o,

  output logic                                     dram_req_valid_o,
  input  logic                                     dram_req_ready_i,
  output rpu_pkg::dram_req_t                       dram_req_o,
  input  logic                                     dram_rsp_valid_i,
  output logic                                     dram_rsp_ready_o,
  input  rpu_pkg::dram_rsp_t                       dram_rsp_i
);

  localparam int unsigned ReqBits   = rpu_pkg::DramReqBits;
  localparam int unsigned RspBits   = rpu_pkg::DramRspBits;
  localparam int unsigned IdBits    = rpu_pkg::DramTagBits - rpu_pkg::DramMshrBits;
  localparam int unsigned IndexBits = Caches > 1 ? $clog2(Caches) : 1;

  logic [IndexBits-1:0] index;
  rpu_rr_arbiter #(.Inputs(Caches), .Width(ReqBits)) u_rr (
    .clk_i, .rst_ni,
    .valid_i(req_valid_i), .ready_o(req_ready_o), .data_i(req_i),
    .valid_o(dram_req_valid_o), .ready_i(dram_req_ready_i), .data_o(dram_req_o), .index_o(index)
  );

  logic [IdBits-1:0] rsp_id;
  assign rsp_id = dram_rsp_i.tag[rpu_pkg::DramTagBits-1 -: IdBits];
  rpu_demux #(.Outputs(Caches), .IndexBits(IdBits)) u_rsp (
    .valid_i(dram_rsp_valid_i), .ready_o(dram_rsp_ready_o), .index_i(rsp_id),
    .valid_o(rsp_valid_o), .ready_i(rsp_ready_i)
  );
  for (genvar c = 0; c < Caches; c++) begin : g_rsp
    assign rsp_o[c*RspBits +: RspBits] = dram_rsp_i;
  end

  logic unused;
  assign unused = ^index;

`ifndef SYNTHESIS
  always_ff @(posedge clk_i or negedge rst_ni) begin : check_tags
    if (rst_ni) begin
      if (dram_req_valid_o) begin
        assert (32'(dram_req_o.tag[rpu_pkg::DramTagBits-1 -: IdBits]) == 32'(index))
          else $error("rpu_mem_arbiter: port %0d sent a request tagged for cache %0d", index,
                      dram_req_o.tag[rpu_pkg::DramTagBits-1 -: IdBits]);
      end
      if (dram_rsp_valid_i) begin
        assert (32'(rsp_id) < Caches)
          else $error("rpu_mem_arbiter: an answer with tag %0h for no cache", dram_rsp_i.tag);
      end
    end
  end
`endif

endmodule
