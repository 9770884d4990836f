// The memory system as sim/mem_cosim.cpp drives it (docs/memory-system.md): a node,
// a triangle and a data cache (CacheId 0, 1, 2) on one memory port through
// rpu_mem_arbiter; each cache behind an rpu_cache_arbiter of RawPorts cache ports and
// InOrderPorts traversal-unit ports (rpu_inorder_port). Each kind of stream is one
// flat port holding every port's, port p at [p*<Stream>Bits +: <Stream>Bits], raw port
// r of cache c being p = c*RawPorts + r. Only wiring, and geometry_o: the parameters
// the model was built with, which the harness reads instead of being told them.
//
// The defaults are corner cases (a fully associative write-back cache with one miss
// register, a direct-mapped write-through one with a 4-cycle hit, a 2-way write-back one
// with 16 miss registers); each
// named configuration's come from spec/configs.toml (gen.py --list rtl-configs).
module rpu_mem_system #(
  parameter int unsigned NodeBytes          = 256,
  parameter int unsigned NodeWays           = 4,
  parameter int unsigned NodeHitLatency     = 3,
  parameter int unsigned NodeMshrs          = 1,
  parameter int unsigned NodeWriteBack      = 1,
  parameter int unsigned TriangleBytes      = 128,
  parameter int unsigned TriangleWays       = 1,
  parameter int unsigned TriangleHitLatency = 4,
  parameter int unsigned TriangleMshrs      = 3,
  parameter int unsigned TriangleWriteBack  = 0,
  parameter int unsigned DataBytes          = 512,
  parameter int unsigned DataWays           = 2,
  parameter int unsigned DataHitLatency     = 2,
  parameter int unsigned DataMshrs          = 16,
  parameter int unsigned DataWriteBack      = 1,
  localparam int unsigned Caches       = 3,
  localparam int unsigned RawPorts     = 2,
  localparam int unsigned InOrderPorts = 1,
  localparam int unsigned Raw          = Caches * RawPorts,
  localparam int unsigned InOrder      = Caches * InOrderPorts
) (
  input  logic                                          clk_i,
  input  logic                                          rst_ni,

  input  logic [Caches-1:0]                             flush_i,     // each cache's (rpu_cache)

  input  logic [Raw-1:0]                                req_valid_i,
  output logic [Raw-1:0]                                req_ready_o,
  input  logic [Raw*rpu_pkg::CacheReqBits-1:0]          req_i,
  output logic [Raw-1:0]                                rsp_valid_o,
  input  logic [Raw-1:0]                                rsp_ready_i,
  output logic [Raw*rpu_pkg::CacheRspBits-1:0]          rsp_o,

  input  logic [InOrder-1:0]                            mem_req_valid_i,
  output logic [InOrder-1:0]                            mem_req_ready_o,
  input  logic [InOrder*rpu_pkg::MemReqBits-1:0]        mem_req_i,
  output logic [InOrder-1:0]                            mem_rsp_valid_o,
  input  logic [InOrder-1:0]                            mem_rsp_ready_i,
  output logic [InOrder*rpu_pkg::MemRspBits-1:0]        mem_rsp_o,

  output logic                                          dram_req_valid_o,
  input  logic                                          dram_req_ready_i,
  output logic [rpu_pkg::DramReqBits-1:0]               dram_req_o,
  input  logic                                          dram_rsp_valid_i,
  output logic                                          dram_rsp_ready_o,
  input  logic [rpu_pkg::DramRspBits-1:0]               dram_rsp_i,

  output logic [Caches*rpu_pkg::CacheCountersBits-1:0]  counters_o,
  output logic [Caches-1:0]                             idle_o,      // the cache and its in-order ports
  output logic [Caches-1:0]                             dirty_o,     // the cache's (rpu_cache)
  output logic [Caches*rpu_pkg::CacheGeometryBits-1:0]  geometry_o  // the caches' parameters
);

  localparam int unsigned Ports       = RawPorts + InOrderPorts;
  localparam int unsigned CacheReq    = rpu_pkg::CacheReqBits;
  localparam int unsigned CacheRsp    = rpu_pkg::CacheRspBits;
  localparam int unsigned OwnTagBits  = rpu_pkg::CacheTagBits - $clog2(Ports);

  logic [Caches-1:0]                      dq_valid, dq_ready, dr_valid, dr_ready;
  logic [Caches*rpu_pkg::DramReqBits-1:0] dq;
  logic [Caches*rpu_pkg::DramRspBits-1:0] dr;

  for (genvar c = 0; c < Caches; c++) begin : g_cache
    localparam int unsigned Bytes      = c == 0 ? NodeBytes : c == 1 ? TriangleBytes : DataBytes;
    localparam int unsigned Ways       = c == 0 ? NodeWays : c == 1 ? TriangleWays : DataWays;
    localparam int unsigned HitLatency = c == 0 ? NodeHitLatency : c == 1 ? TriangleHitLatency : DataHitLatency;
    localparam int unsigned Mshrs      = c == 0 ? NodeMshrs : c == 1 ? TriangleMshrs : DataMshrs;
    localparam int unsigned WriteBack  = c == 0 ? NodeWriteBack : c == 1 ? TriangleWriteBack : DataWriteBack;

    // The arbiter's ports: the raw ports first, then the in-order ports.
    logic [Ports-1:0]          p_req_valid, p_req_ready, p_rsp_valid, p_rsp_ready;
    logic [Ports*CacheReq-1:0] p_req;
    logic [Ports*CacheRsp-1:0] p_rsp;
    assign p_req_valid[RawPorts-1:0]        = req_valid_i[c*RawPorts +: RawPorts];
    assign p_req[RawPorts*CacheReq-1:0]     = req_i[c*RawPorts*CacheReq +: RawPorts*CacheReq];
    assign req_ready_o[c*RawPorts +: RawPorts] = p_req_ready[RawPorts-1:0];
    assign rsp_valid_o[c*RawPorts +: RawPorts] = p_rsp_valid[RawPorts-1:0];
    assign p_rsp_ready[RawPorts-1:0]        = rsp_ready_i[c*RawPorts +: RawPorts];
    assign rsp_o[c*RawPorts*CacheRsp +: RawPorts*CacheRsp] = p_rsp[RawPorts*CacheRsp-1:0];

    logic [InOrderPorts-1:0] io_idle;
    for (genvar i = 0; i < InOrderPorts; i++) begin : g_inorder
      localparam int unsigned P = RawPorts + i;  // its arbiter port
      localparam int unsigned T = c * InOrderPorts + i;  // its top-level port
      rpu_inorder_port #(.TagBits(OwnTagBits)) u_port (
        .clk_i, .rst_ni,
        .mem_req_valid_i(mem_req_valid_i[T]), .mem_req_ready_o(mem_req_ready_o[T]),
        .mem_req_i(mem_req_i[T*rpu_pkg::MemReqBits +: rpu_pkg::MemReqBits]),
        .mem_rsp_valid_o(mem_rsp_valid_o[T]), .mem_rsp_ready_i(mem_rsp_ready_i[T]),
        .mem_rsp_o(mem_rsp_o[T*rpu_pkg::MemRspBits +: rpu_pkg::MemRspBits]),
        .cache_req_valid_o(p_req_valid[P]), .cache_req_ready_i(p_req_ready[P]),
        .cache_req_o(p_req[P*CacheReq +: CacheReq]),
        .cache_rsp_valid_i(p_rsp_valid[P]), .cache_rsp_ready_o(p_rsp_ready[P]),
        .cache_rsp_i(p_rsp[P*CacheRsp +: CacheRsp]),
        .idle_o(io_idle[i])
      );
    end

    logic                c_req_valid, c_req_ready, c_rsp_valid, c_rsp_ready;
    logic [CacheReq-1:0] c_req;
    logic [CacheRsp-1:0] c_rsp;
    rpu_cache_arbiter #(.Requesters(Ports)) u_arbiter (
      .clk_i, .rst_ni,
      .req_valid_i(p_req_valid), .req_ready_o(p_req_ready), .req_i(p_req),
      .rsp_valid_o(p_rsp_valid), .rsp_ready_i(p_rsp_ready), .rsp_o(p_rsp),
      .cache_req_valid_o(c_req_valid), .cache_req_ready_i(c_req_ready), .cache_req_o(c_req),
      .cache_rsp_valid_i(c_rsp_valid), .cache_rsp_ready_o(c_rsp_ready), .cache_rsp_i(c_rsp)
    );

    logic cache_idle;
    assign idle_o[c] = cache_idle && &io_idle;
    rpu_cache #(
      .Bytes(Bytes), .Ways(Ways), .HitLatency(HitLatency), .Mshrs(Mshrs), .WriteBack(WriteBack), .CacheId(c)
    ) u_cache (
      .clk_i, .rst_ni, .flush_i(flush_i[c]),
      .req_valid_i(c_req_valid), .req_ready_o(c_req_ready), .req_i(c_req),
      .rsp_valid_o(c_rsp_valid), .rsp_ready_i(c_rsp_ready), .rsp_o(c_rsp),
      .dram_req_valid_o(dq_valid[c]), .dram_req_ready_i(dq_ready[c]),
      .dram_req_o(dq[c*rpu_pkg::DramReqBits +: rpu_pkg::DramReqBits]),
      .dram_rsp_valid_i(dr_valid[c]), .dram_rsp_ready_o(dr_ready[c]),
      .dram_rsp_i(dr[c*rpu_pkg::DramRspBits +: rpu_pkg::DramRspBits]),
      .counters_o(counters_o[c*rpu_pkg::CacheCountersBits +: rpu_pkg::CacheCountersBits]),
      .idle_o(cache_idle), .dirty_o(dirty_o[c])
    );

    assign geometry_o[c*rpu_pkg::CacheGeometryBits +: rpu_pkg::CacheGeometryBits] =
        {32'(Bytes), 32'(Ways), 32'(HitLatency), 32'(Mshrs), 32'(WriteBack)};
  end

  rpu_mem_arbiter #(.Caches(Caches)) u_mem_arbiter (
    .clk_i, .rst_ni,
    .req_valid_i(dq_valid), .req_ready_o(dq_ready), .req_i(dq),
    .rsp_valid_o(dr_valid), .rsp_ready_i(dr_ready), .rsp_o(dr),
    .dram_req_valid_o, .dram_req_ready_i, .dram_req_o,
    .dram_rsp_valid_i, .dram_rsp_ready_o, .dram_rsp_i
  );

endmodule
