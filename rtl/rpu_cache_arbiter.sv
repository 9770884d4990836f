// Requesters onto one cache port, round robin (rpu_rr_arbiter): the node and triangle
// caches are shared by the chip's traversal units (docs/memory-system.md). A request's
// tag leaves with the requester's index in its high bits, so the cache sees distinct
// tags; an answer goes back to the requester its tag's high bits name, with them
// cleared. A requester's own tags must fit the OwnTagBits low bits (checked). One
// requester passes through unchanged.
module rpu_cache_arbiter #(
  parameter int unsigned Requesters = 2,
  localparam int unsigned IndexBits  = Requesters > 1 ? $clog2(Requesters) : 0,
  localparam int unsigned OwnTagBits = rpu_pkg::CacheTagBits - IndexBits
) (
  input  logic                                         clk_i,
  input  logic                                         rst_ni,

  input  logic [Requesters-1:0]                        req_valid_i,
  output logic [Requesters-1:0]                        req_ready_o,
  input  logic [Requesters*rpu_pkg::CacheReqBits-1:0]  req_i,  // requester r's at [r*CacheReqBits +: CacheReqBits]
  output logic [Requesters-1:0]                        rsp_valid_o,
  input  logic [Requesters-1:0]                        rsp_ready_i,
  output logic [Requesters*rpu_pkg::CacheRspBits-1:0]  rsp_o,

  output logic                                         cache_req_valid_o,
  input  logic                                         cache_req_ready_i,
  output rpu_pkg::cache_req_t                          cache_req_o,
  input  logic                                         cache_rsp_valid_i,
  output logic                                         cache_rsp_ready_o,
  input  rpu_pkg::cache_rsp_t                          cache_rsp_i
);

  localparam int unsigned ReqBits = rpu_pkg::CacheReqBits;
  localparam int unsigned RspBits = rpu_pkg::CacheRspBits;
  localparam int unsigned TagBits = rpu_pkg::CacheTagBits;

  if (Requesters == 1) begin : g_one
    assign cache_req_valid_o = req_valid_i[0];
    assign req_ready_o       = cache_req_ready_i;
    assign cache_req_o       = req_i;
    assign rsp_valid_o       = cache_rsp_valid_i;
    assign cache_rsp_ready_o = rsp_ready_i[0];
    assign rsp_o             = cache_rsp_i;
    logic unused;
    assign unused = ^{clk_i, rst_ni};
  end else begin : g_many
    // The tag field is the request's top TagBits bits (spec/streams.toml, first field).
    logic [Requesters*ReqBits-1:0] indexed;
    for (genvar r = 0; r < Requesters; r++) begin : g_tag
      assign indexed[r*ReqBits +: ReqBits] = {IndexBits'(r), req_i[r*ReqBits +: ReqBits-IndexBits]};
    end
    logic [IndexBits-1:0] index;
    rpu_rr_arbiter #(.Inputs(Requesters), .Width(ReqBits)) u_rr (
      .clk_i, .rst_ni,
      .valid_i(req_valid_i), .ready_o(req_ready_o), .data_i(indexed),
      .valid_o(cache_req_valid_o), .ready_i(cache_req_ready_i), .data_o(cache_req_o), .index_o(index)
    );

    logic [IndexBits-1:0] rsp_index;
    logic [RspBits-1:0]   own_rsp;  // the answer with the index bits cleared
    assign rsp_index = cache_rsp_i.tag[TagBits-1 -: IndexBits];
    assign own_rsp   = {IndexBits'(0), cache_rsp_i[RspBits-IndexBits-1:0]};
    rpu_demux #(.Outputs(Requesters), .IndexBits(IndexBits)) u_rsp (
      .valid_i(cache_rsp_valid_i), .ready_o(cache_rsp_ready_o), .index_i(rsp_index),
      .valid_o(rsp_valid_o), .ready_i(rsp_ready_i)
    );
    for (genvar r = 0; r < Requesters; r++) begin : g_rsp
      assign rsp_o[r*RspBits +: RspBits] = own_rsp;
    end

    logic unused;
    assign unused = ^index;

`ifndef SYNTHESIS
    always_ff @(posedge clk_i or negedge rst_ni) begin : check_tags
      if (rst_ni) begin
        for (int r = 0; r < Requesters; r++) begin
          if (req_valid_i[r]) begin
            assert (req_i[r*ReqBits + ReqBits - 1 -: IndexBits] == '0)
              else $error("rpu_cache_arbiter: requester %0d's tag %0h is wider than %0d bits", r,
                          req_i[r*ReqBits + ReqBits - 1 -: TagBits], OwnTagBits);
          end
        end
        if (cache_rsp_valid_i) begin
          assert (32'(rsp_index) < Requesters)
            else $error("rpu_cache_arbiter: an answer with tag %0h for no requester", cache_rsp_i.tag);
        end
      end
    end
`endif
  end

endmodule
