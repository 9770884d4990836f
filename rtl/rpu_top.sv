// The chip (docs/chip.md): Cores shader cores (rpu_spu), each with its data cache;
// RayUnits ray units (rpu_ray_unit: a traversal unit and its intersection unit) fed by
// rpu_ray_dispatch, their memory ports on a node cache (kd nodes) and a triangle cache
// (leaf lists and intersection records) of RayCaches pairs, each pair shared by
// RayUnits / RayCaches units, answered in order (rpu_inorder_port) or with TuByTag by
// tag, as the caches answer; every cache on one memory port (rpu_mem_arbiter). Built for a named configuration of
// spec/configs.toml (its parameters from gen.py --list rtl-configs).
//
// The host writes the firmware into every core's code memory, holds the launch and the
// scene's traversal configuration, and pulses start_i; done_o rises when every core has
// run its rounds of pixels, the write-back caches have written their dirty lines, and
// nothing is in flight. A fault anywhere stops every round
// past the first faulting pixel (stop logic below). The trace ports repeat each core's
// issue, retire, writeback and fault records for the lockstep checker; the counters
// count the cycles from the one after start_i to the one before done_o.
module rpu_top #(
  parameter int unsigned Cores               = rpu_pkg::ConfigTinyShaderCores,
  parameter int unsigned Threads             = rpu_pkg::ConfigTinyThreadsPerCore,
  parameter int unsigned ChunkSize           = rpu_pkg::ConfigTinyChunkSize,
  parameter int unsigned IssueLanes          = rpu_pkg::ConfigTinyIssueLanes,
  parameter int unsigned Registers           = rpu_pkg::ConfigTinyRegisters,
  parameter int unsigned CallDepth           = rpu_pkg::ConfigTinyCallDepth,
  parameter int unsigned StackBytes          = rpu_pkg::ConfigTinyStackBytes,
  parameter int unsigned SfuUnits            = rpu_pkg::ConfigTinySfuUnits,
  parameter int unsigned SfuThreads          = rpu_pkg::ConfigTinySfuThreads,
  parameter int unsigned StackDepth          = rpu_pkg::ConfigTinyStackDepth,
  parameter int unsigned RayUnits            = rpu_pkg::ConfigTinyTraversalUnits,
  parameter int unsigned RayCaches           = rpu_pkg::ConfigTinyRayCaches,
  parameter int unsigned TuSlots             = rpu_pkg::ConfigTinyTuSlots,
  parameter int unsigned TuPipe              = rpu_pkg::ConfigTinyTuPipe,
  parameter int unsigned TuSetups            = rpu_pkg::ConfigTinyTuSetups,
  parameter int unsigned TuByTag             = rpu_pkg::ConfigTinyTuByTag,
  parameter int unsigned TuPacket            = rpu_pkg::ConfigTinyTuPacket,
  parameter int unsigned IsectMode           = rpu_pkg::IsectModeWoop,
  parameter int unsigned NodeBytes      = rpu_pkg::ConfigTinyNodeCacheBytes,
  parameter int unsigned NodeWays       = rpu_pkg::ConfigTinyNodeCacheWays,
  parameter int unsigned NodeHitLatency = rpu_pkg::ConfigTinyNodeCacheHitLatency,
  parameter int unsigned NodeMshrs      = rpu_pkg::ConfigTinyNodeCacheMshrs,
  parameter int unsigned NodeWriteBack  = rpu_pkg::ConfigTinyNodeCacheWriteBack,
  parameter int unsigned TriangleBytes      = rpu_pkg::ConfigTinyTriangleCacheBytes,
  parameter int unsigned TriangleWays       = rpu_pkg::ConfigTinyTriangleCacheWays,
  parameter int unsigned TriangleHitLatency = rpu_pkg::ConfigTinyTriangleCacheHitLatency,
  parameter int unsigned TriangleMshrs      = rpu_pkg::ConfigTinyTriangleCacheMshrs,
  parameter int unsigned TriangleWriteBack  = rpu_pkg::ConfigTinyTriangleCacheWriteBack,
  parameter int unsigned DataBytes      = rpu_pkg::ConfigTinyDataCacheBytes,
  parameter int unsigned DataWays       = rpu_pkg::ConfigTinyDataCacheWays,
  parameter int unsigned DataHitLatency = rpu_pkg::ConfigTinyDataCacheHitLatency,
  parameter int unsigned DataMshrs      = rpu_pkg::ConfigTinyDataCacheMshrs,
  parameter int unsigned DataWriteBack  = rpu_pkg::ConfigTinyDataCacheWriteBack,
  parameter int unsigned CodeWords           = 4096,
  parameter int unsigned ExpBits             = rpu_pkg::FormatFp32ExponentBits,
  parameter int unsigned FracBits            = rpu_pkg::FormatFp32FractionBits,
  localparam int unsigned CodeAddrBits = $clog2(CodeWords)
) (
  input  logic                                    clk_i,
  input  logic                                    rst_ni,

  input  logic                                    code_we_i,
  input  logic [CodeAddrBits-1:0]                 code_addr_i,
  input  logic [63:0]                             code_data_i,

  input  logic                                    start_i,
  input  rpu_pkg::launch_t                        launch_i,
  input  rpu_pkg::tu_cfg_t                        tu_cfg_i,
  output logic                                    done_o,

  output logic                                    dram_req_valid_o,
  input  logic                                    dram_req_ready_i,
  output rpu_pkg::dram_req_t                      dram_req_o,
  input  logic                                    dram_rsp_valid_i,
  output logic                                    dram_rsp_ready_o,
  input  rpu_pkg::dram_rsp_t                      dram_rsp_i,

  output logic [Cores-1:0]                        issue_valid_o,
  output logic [Cores*rpu_pkg::IssueBits-1:0]     issue_o,
  // retire and writeback: IssueLanes records per core (its ways), core c's at c x IssueLanes.
  output logic [Cores*IssueLanes-1:0]             retire_valid_o,
  output logic [Cores*IssueLanes*rpu_pkg::RetireBits-1:0] retire_o,
  output logic [Cores*IssueLanes-1:0]             wb_valid_o,
  output logic [Cores*IssueLanes*rpu_pkg::WritebackBits-1:0] wb_o,
  output logic [Cores-1:0]                        fault_valid_o,
  output logic [Cores*rpu_pkg::FaultBits-1:0]     fault_o,

  // Counters of the frame (docs/chip.md "Statistics"): per core, per ray unit, and per
  // cache (pair p's node cache at p, its triangle cache at RayCaches + p, then core c's
  // data cache at 2 x RayCaches + c).
  output logic [Cores*rpu_pkg::CoreCountersBits-1:0]        core_counters_o,
  output logic [RayUnits*rpu_pkg::RayUnitCountersBits-1:0]  ray_counters_o,
  output logic [(2*RayCaches+Cores)*rpu_pkg::CacheCountersBits-1:0] cache_counters_o
);

  // The memory port's caches: the node caches, the triangle caches, a data cache per core.
  localparam int unsigned NodeCache = 0;
  localparam int unsigned TriangleCache = 1;
  localparam int unsigned RayCaches2 = 2 * RayCaches;
  localparam int unsigned Caches = RayCaches2 + Cores;
  // The ray units one pair of caches serves.
  localparam int unsigned PairUnits = RayUnits / RayCaches;
`ifndef SYNTHESIS
  initial begin : check_pairs
    assert (RayCaches >= 1 && RayUnits % RayCaches == 0)
      else $fatal(1, "rpu_top: %0d cache pairs do not divide %0d ray units", RayCaches, RayUnits);
  end
`endif
  localparam int unsigned ReqBits = rpu_pkg::CacheReqBits;
  localparam int unsigned RspBits = rpu_pkg::CacheRspBits;
  // A ray unit's tags at the node and triangle caches: what their arbiters leave of
  // the cache tag (rpu_cache_arbiter's OwnTagBits); spec/streams.py checks that a record's
  // lines fit.
  localparam int unsigned PortTagBits = rpu_pkg::CacheTagBits - (PairUnits > 1 ? $clog2(PairUnits) : 0);
  // A walker has at most an intersection record's lines in flight per slot, so its
  // in-order port's reorder buffer holds that many; a pipelined unit's, every line its
  // tags name.
  localparam int unsigned WalkerLines = TuSlots * rpu_pkg::IsectRecordWords * 4 / rpu_pkg::MemLineBytes;
  localparam int unsigned InOrderTagBits = TuPipe != 0 ? PortTagBits : $clog2(WalkerLines);

  logic [Caches-1:0]                      c_dram_req_valid, c_dram_req_ready, c_dram_rsp_valid, c_dram_rsp_ready;
  logic [Caches*rpu_pkg::DramReqBits-1:0] c_dram_req;
  logic [Caches*rpu_pkg::DramRspBits-1:0] c_dram_rsp;
  logic [Caches-1:0]                      cache_idle, cache_dirty;

  // The frame: counters count from the cycle after start_i until done_o.
  logic frame_d, frame_q, count;
  assign frame_d = start_i || frame_q;
  assign count   = frame_q && !done_o;

  // ---------------------------------------------------------------------------------
  // The chip's inputs, registered: the launch and the scene's traversal configuration
  // (held for the frame; start_i is delayed with them, so the cores see all three in
  // the same cycle) and the memory port's answers (a skid buffer). Nothing inside then
  // depends combinationally on a pin, which is also what lets Verilator evaluate the
  // logic once a cycle instead of again for every change of an input.
  // ---------------------------------------------------------------------------------
  logic               start_q;
  rpu_pkg::launch_t   launch_q;
  rpu_pkg::tu_cfg_t   tu_cfg_q;
  logic               port_rsp_valid, port_rsp_ready;
  rpu_pkg::dram_rsp_t port_rsp;
  rpu_skid_buf #(.Width(rpu_pkg::DramRspBits)) u_dram_rsp (
    .clk_i, .rst_ni,
    .valid_i(dram_rsp_valid_i), .ready_o(dram_rsp_ready_o), .data_i(dram_rsp_i),
    .valid_o(port_rsp_valid), .ready_i(port_rsp_ready), .data_o(port_rsp)
  );

  // ---------------------------------------------------------------------------------
  // Stop: the first faulting pixel seen so far; no round past it starts.
  // ---------------------------------------------------------------------------------
  logic            stop_d, stop_q;
  logic [31:0]     stop_pixel_d, stop_pixel_q;
  rpu_pkg::fault_t fault;
  always_comb begin : find_stop
    stop_d       = stop_q && !start_i;
    stop_pixel_d = stop_pixel_q;
    fault        = '0;
    for (int c = 0; c < Cores; c++) begin
      fault = fault_o[rpu_pkg::FaultBits*c +: rpu_pkg::FaultBits];
      if (fault_valid_o[c]) begin
        if (!stop_d || fault.pixel < stop_pixel_d) stop_pixel_d = fault.pixel;
        stop_d = 1'b1;
      end
    end
  end

  // ---------------------------------------------------------------------------------
  // Shader cores, each with its data cache.
  // ---------------------------------------------------------------------------------
  logic [Cores-1:0]                      core_done;
  // Once every core is done, the write-back caches write their dirty lines to memory
  // (rpu_cache flush_i), and done_o waits for them (dirty_o, idle_o).
  logic                                  flush;
  assign flush = &core_done && !start_q;
  logic [Cores-1:0]                      t_req_valid, t_req_ready, t_rsp_valid, t_rsp_ready;
  logic [Cores*rpu_pkg::TraceReqBits-1:0] t_req;
  logic [Cores*rpu_pkg::TraceRspBits-1:0] t_rsp;

  for (genvar c = 0; c < Cores; c++) begin : g_core
    logic                 req_valid, req_ready, rsp_valid, rsp_ready;
    logic [ReqBits-1:0]   req;
    logic [RspBits-1:0]   rsp;

    rpu_spu #(
      .CoreId(c), .Cores(Cores), .Threads(Threads), .ChunkSize(ChunkSize), .IssueLanes(IssueLanes),
      .Registers(Registers),
      .CallDepth(CallDepth), .StackBytes(StackBytes), .SfuUnits(SfuUnits), .SfuThreads(SfuThreads),
      .CodeWords(CodeWords),
      .ExpBits(ExpBits), .FracBits(FracBits)
    ) u_spu (
      .clk_i, .rst_ni,
      .code_we_i, .code_addr_i, .code_data_i,
      .start_i(start_q), .launch_i(launch_q), .stop_i(stop_q), .stop_pixel_i(stop_pixel_q), .done_o(core_done[c]),
      .count_i(count), .counters_o(core_counters_o[rpu_pkg::CoreCountersBits*c +: rpu_pkg::CoreCountersBits]),
      .cache_req_valid_o(req_valid), .cache_req_ready_i(req_ready), .cache_req_o(req),
      .cache_rsp_valid_i(rsp_valid), .cache_rsp_ready_o(rsp_ready), .cache_rsp_i(rsp),
      .trace_req_valid_o(t_req_valid[c]), .trace_req_ready_i(t_req_ready[c]),
      .trace_req_o(t_req[rpu_pkg::TraceReqBits*c +: rpu_pkg::TraceReqBits]),
      .trace_rsp_valid_i(t_rsp_valid[c]), .trace_rsp_ready_o(t_rsp_ready[c]),
      .trace_rsp_i(t_rsp[rpu_pkg::TraceRspBits*c +: rpu_pkg::TraceRspBits]),
      .issue_valid_o(issue_valid_o[c]), .issue_o(issue_o[rpu_pkg::IssueBits*c +: rpu_pkg::IssueBits]),
      .retire_valid_o(retire_valid_o[IssueLanes*c +: IssueLanes]),
      .retire_o(retire_o[IssueLanes*rpu_pkg::RetireBits*c +: IssueLanes*rpu_pkg::RetireBits]),
      .wb_valid_o(wb_valid_o[IssueLanes*c +: IssueLanes]),
      .wb_o(wb_o[IssueLanes*rpu_pkg::WritebackBits*c +: IssueLanes*rpu_pkg::WritebackBits]),
      .fault_valid_o(fault_valid_o[c]), .fault_o(fault_o[rpu_pkg::FaultBits*c +: rpu_pkg::FaultBits])
    );

    rpu_cache #(
      .Bytes(DataBytes), .Ways(DataWays), .HitLatency(DataHitLatency), .Mshrs(DataMshrs),
      .WriteBack(DataWriteBack), .CacheId(RayCaches2 + c)
    ) u_data_cache (
      .clk_i, .rst_ni, .flush_i(flush),
      .req_valid_i(req_valid), .req_ready_o(req_ready), .req_i(req),
      .rsp_valid_o(rsp_valid), .rsp_ready_i(rsp_ready), .rsp_o(rsp),
      .dram_req_valid_o(c_dram_req_valid[RayCaches2 + c]), .dram_req_ready_i(c_dram_req_ready[RayCaches2 + c]),
      .dram_req_o(c_dram_req[rpu_pkg::DramReqBits*(RayCaches2 + c) +: rpu_pkg::DramReqBits]),
      .dram_rsp_valid_i(c_dram_rsp_valid[RayCaches2 + c]), .dram_rsp_ready_o(c_dram_rsp_ready[RayCaches2 + c]),
      .dram_rsp_i(c_dram_rsp[rpu_pkg::DramRspBits*(RayCaches2 + c) +: rpu_pkg::DramRspBits]),
      .counters_o(cache_counters_o[rpu_pkg::CacheCountersBits*(RayCaches2 + c) +: rpu_pkg::CacheCountersBits]),
      .idle_o(cache_idle[RayCaches2 + c]), .dirty_o(cache_dirty[RayCaches2 + c])
    );
  end

  // ---------------------------------------------------------------------------------
  // Ray units, their rays from the cores.
  // ---------------------------------------------------------------------------------
  logic [RayUnits-1:0]                      u_req_valid, u_req_ready, u_rsp_valid, u_rsp_ready;
  logic [RayUnits*rpu_pkg::TuReqBits-1:0]   u_req;
  logic [RayUnits*rpu_pkg::TuRspBits-1:0]   u_rsp;
  logic                                     dispatch_idle;

  // The rays a unit may hold: a walker's one per slot; a pipelined unit's slots (of
  // TuPacket rays each), three per set-up engine (its input buffer's two and the one it
  // works on) and the two of the answer's skid buffer below, to a power of two.
  localparam int unsigned UnitRays = TuPipe != 0 ? 1 << $clog2(TuSlots * TuPacket + 3 * TuSetups + 2) : TuSlots;

  rpu_ray_dispatch #(.Cores(Cores), .Units(RayUnits), .UnitRays(UnitRays), .Packets(TuPacket > 1 ? 1 : 0)) u_dispatch (
    .clk_i, .rst_ni,
    .core_req_valid_i(t_req_valid), .core_req_ready_o(t_req_ready), .core_req_i(t_req),
    .core_rsp_valid_o(t_rsp_valid), .core_rsp_ready_i(t_rsp_ready), .core_rsp_o(t_rsp),
    .unit_req_valid_o(u_req_valid), .unit_req_ready_i(u_req_ready), .unit_req_o(u_req),
    .unit_rsp_valid_i(u_rsp_valid), .unit_rsp_ready_o(u_rsp_ready), .unit_rsp_i(u_rsp),
    .idle_o(dispatch_idle)
  );

  // Each unit's memory port, in order or by tag, on the node cache (the kd nodes, which
  // the image lays out before the leaf lists) or the triangle cache (the rest); which
  // one decides only where a line is kept, never what is read. A walker waits for each of
  // its requests' answers before it asks the other cache, so answers from the two never
  // meet at one port; a pipelined unit's may, and the node cache's goes first (the
  // in-order port reorders them; by tag, the unit takes them as they come). Requests to
  // cache kind k (NodeCache, TriangleCache) from unit u sit at index k * RayUnits + u, so
  // pair p's units are PairUnits neighbours from k * RayUnits + p * PairUnits.
  logic [2*RayUnits-1:0]         k_req_valid, k_req_ready, k_rsp_valid, k_rsp_ready;
  logic [2*RayUnits*ReqBits-1:0] k_req;
  logic [2*RayUnits*RspBits-1:0] k_rsp;
  logic [RayUnits-1:0]           port_idle;

  for (genvar u = 0; u < RayUnits; u++) begin : g_ray_unit
    logic                             mem_req_valid, mem_req_ready, mem_rsp_valid, mem_rsp_ready;
    logic [rpu_pkg::MemReqBits-1:0]   mem_req;
    logic [rpu_pkg::MemRspBits-1:0]   mem_rsp;
    logic                             p_req_valid, p_req_ready, p_rsp_valid, p_rsp_ready;
    logic [ReqBits-1:0]               p_req;
    logic [RspBits-1:0]               p_rsp;
    logic                             to_node;

    // rpu_tu decides every output in one process, from every input: skid buffers on its
    // answers and its memory requests keep the readies it sees registered, so no
    // combinational path runs from its outputs back into it through the dispatcher or the
    // caches.
    logic                             a_valid, a_ready, q_valid, q_ready;
    logic [rpu_pkg::TuRspBits-1:0]    a;
    logic [rpu_pkg::MemReqBits-1:0]   q;

    rpu_ray_unit #(.ExpBits(ExpBits), .FracBits(FracBits), .IsectMode(IsectMode), .StackDepth(StackDepth),
                   .TuSlots(TuSlots), .TuPipe(TuPipe), .TuPacket(TuPacket), .TuSetups(TuSetups),
                   .LineTagBits(PortTagBits)) u_unit (
      .clk_i, .rst_ni, .cfg_i(tu_cfg_q),
      .req_valid_i(u_req_valid[u]), .req_ready_o(u_req_ready[u]),
      .req_i(u_req[rpu_pkg::TuReqBits*u +: rpu_pkg::TuReqBits]),
      .rsp_valid_o(a_valid), .rsp_ready_i(a_ready), .rsp_o(a),
      .mem_req_valid_o(q_valid), .mem_req_ready_i(q_ready), .mem_req_o(q),
      .mem_rsp_valid_i(mem_rsp_valid), .mem_rsp_ready_o(mem_rsp_ready), .mem_rsp_i(mem_rsp),
      .count_i(count),
      .counters_o(ray_counters_o[rpu_pkg::RayUnitCountersBits*u +: rpu_pkg::RayUnitCountersBits])
    );
    rpu_skid_buf #(.Width(rpu_pkg::TuRspBits)) u_answer (
      .clk_i, .rst_ni,
      .valid_i(a_valid), .ready_o(a_ready), .data_i(a),
      .valid_o(u_rsp_valid[u]), .ready_i(u_rsp_ready[u]), .data_o(u_rsp[rpu_pkg::TuRspBits*u +: rpu_pkg::TuRspBits])
    );
    rpu_skid_buf #(.Width(rpu_pkg::MemReqBits)) u_request (
      .clk_i, .rst_ni,
      .valid_i(q_valid), .ready_o(q_ready), .data_i(q),
      .valid_o(mem_req_valid), .ready_i(mem_req_ready), .data_o(mem_req)
    );

    if (TuByTag != 0) begin : g_by_tag
      // The unit's tags go to the caches as they are; answers come back as they leave.
      rpu_pkg::mem_req_t unit_req;
      rpu_pkg::cache_req_t by_tag_req;
      rpu_pkg::cache_rsp_t by_tag_rsp;
      rpu_pkg::mem_rsp_t unit_rsp;
      assign unit_req          = mem_req;
      assign by_tag_req.tag    = unit_req.tag;
      assign by_tag_req.addr   = unit_req.addr;
      assign by_tag_req.write  = 1'b0;
      assign by_tag_req.wmask  = '0;
      assign by_tag_req.data   = '0;
      assign p_req             = by_tag_req;
      assign p_req_valid       = mem_req_valid;
      assign mem_req_ready     = p_req_ready;
      assign by_tag_rsp        = p_rsp;
      assign unit_rsp.tag      = by_tag_rsp.tag;
      assign unit_rsp.data     = by_tag_rsp.data;
      assign mem_rsp           = unit_rsp;
      assign mem_rsp_valid     = p_rsp_valid;
      assign p_rsp_ready       = mem_rsp_ready;
      assign port_idle[u]      = 1'b1;  // the unit and the caches hold what is in flight
`ifndef SYNTHESIS
      initial begin
        assert (TuPipe != 0) else $fatal(1, "rpu_top: TuByTag needs TuPipe: a walker takes its answers in order");
      end
`endif
    end else begin : g_in_order
      rpu_inorder_port #(.TagBits(InOrderTagBits)) u_port (
        .clk_i, .rst_ni,
        .mem_req_valid_i(mem_req_valid), .mem_req_ready_o(mem_req_ready), .mem_req_i(mem_req),
        .mem_rsp_valid_o(mem_rsp_valid), .mem_rsp_ready_i(mem_rsp_ready), .mem_rsp_o(mem_rsp),
        .cache_req_valid_o(p_req_valid), .cache_req_ready_i(p_req_ready), .cache_req_o(p_req),
        .cache_rsp_valid_i(p_rsp_valid), .cache_rsp_ready_o(p_rsp_ready), .cache_rsp_i(p_rsp),
        .idle_o(port_idle[u])
      );
    end

    // The request's address: the field below the tag (cache_req_t {tag, addr, ...}).
    logic [31:0] addr;
    localparam int unsigned N = NodeCache * RayUnits + u, T = TriangleCache * RayUnits + u;
    assign addr    = p_req[ReqBits - rpu_pkg::CacheTagBits - 1 -: 32];
    assign to_node = addr >= tu_cfg_q.kd_nodes && addr < tu_cfg_q.prim_refs;
    assign k_req_valid[N] = p_req_valid && to_node;
    assign k_req_valid[T] = p_req_valid && !to_node;
    assign p_req_ready    = to_node ? k_req_ready[N] : k_req_ready[T];
    assign k_req[ReqBits*N +: ReqBits] = p_req;
    assign k_req[ReqBits*T +: ReqBits] = p_req;
    assign p_rsp_valid    = k_rsp_valid[N] || k_rsp_valid[T];
    assign p_rsp          = k_rsp_valid[N] ? k_rsp[RspBits*N +: RspBits] : k_rsp[RspBits*T +: RspBits];
    assign k_rsp_ready[N] = p_rsp_ready;
    assign k_rsp_ready[T] = p_rsp_ready && !k_rsp_valid[N];

`ifndef SYNTHESIS
    always_ff @(posedge clk_i or negedge rst_ni) begin : check_answer_sources
      if (rst_ni && TuPipe == 0) begin
        assert (!(k_rsp_valid[N] && k_rsp_valid[T]))
          else $error("rpu_top: ray unit %0d has answers from both caches at once", u);
      end
    end
`endif
  end

  // The node and triangle caches: RayCaches pairs, each shared by PairUnits ray units;
  // cache k * RayCaches + p (its CacheId) is pair p's of kind k.
  for (genvar k = 0; k < 2; k++) begin : g_ray_cache
    for (genvar p = 0; p < RayCaches; p++) begin : g_pair
      localparam int unsigned I = k * RayCaches + p;
      localparam int unsigned First = k * RayUnits + p * PairUnits;  // its first unit's request index
      logic                 req_valid, req_ready, rsp_valid, rsp_ready;
      logic [ReqBits-1:0]   req;
      logic [RspBits-1:0]   rsp;

      rpu_cache_arbiter #(.Requesters(PairUnits)) u_arbiter (
        .clk_i, .rst_ni,
        .req_valid_i(k_req_valid[First +: PairUnits]), .req_ready_o(k_req_ready[First +: PairUnits]),
        .req_i(k_req[ReqBits*First +: ReqBits*PairUnits]),
        .rsp_valid_o(k_rsp_valid[First +: PairUnits]), .rsp_ready_i(k_rsp_ready[First +: PairUnits]),
        .rsp_o(k_rsp[RspBits*First +: RspBits*PairUnits]),
        .cache_req_valid_o(req_valid), .cache_req_ready_i(req_ready), .cache_req_o(req),
        .cache_rsp_valid_i(rsp_valid), .cache_rsp_ready_o(rsp_ready), .cache_rsp_i(rsp)
      );
      rpu_cache #(
        .Bytes(k == NodeCache ? NodeBytes : TriangleBytes),
        .Ways(k == NodeCache ? NodeWays : TriangleWays),
        .HitLatency(k == NodeCache ? NodeHitLatency : TriangleHitLatency),
        .Mshrs(k == NodeCache ? NodeMshrs : TriangleMshrs),
        .WriteBack(k == NodeCache ? NodeWriteBack : TriangleWriteBack),
        .CacheId(I)
      ) u_cache (
        .clk_i, .rst_ni, .flush_i(flush),
        .req_valid_i(req_valid), .req_ready_o(req_ready), .req_i(req),
        .rsp_valid_o(rsp_valid), .rsp_ready_i(rsp_ready), .rsp_o(rsp),
        .dram_req_valid_o(c_dram_req_valid[I]), .dram_req_ready_i(c_dram_req_ready[I]),
        .dram_req_o(c_dram_req[rpu_pkg::DramReqBits*I +: rpu_pkg::DramReqBits]),
        .dram_rsp_valid_i(c_dram_rsp_valid[I]), .dram_rsp_ready_o(c_dram_rsp_ready[I]),
        .dram_rsp_i(c_dram_rsp[rpu_pkg::DramRspBits*I +: rpu_pkg::DramRspBits]),
        .counters_o(cache_counters_o[rpu_pkg::CacheCountersBits*I +: rpu_pkg::CacheCountersBits]),
        .idle_o(cache_idle[I]), .dirty_o(cache_dirty[I])
      );
    end
  end

  // ---------------------------------------------------------------------------------
  // The memory port.
  // ---------------------------------------------------------------------------------
  rpu_mem_arbiter #(.Caches(Caches)) u_mem_arbiter (
    .clk_i, .rst_ni,
    .req_valid_i(c_dram_req_valid), .req_ready_o(c_dram_req_ready), .req_i(c_dram_req),
    .rsp_valid_o(c_dram_rsp_valid), .rsp_ready_i(c_dram_rsp_ready), .rsp_o(c_dram_rsp),
    .dram_req_valid_o, .dram_req_ready_i, .dram_req_o,
    .dram_rsp_valid_i(port_rsp_valid), .dram_rsp_ready_o(port_rsp_ready), .dram_rsp_i(port_rsp)
  );

  // Of a fault, the stop needs only the pixel.
  logic unused_fault;
  assign unused_fault = ^{fault.kind, fault.core, fault.thread, fault.pc, fault.addr};

  // Not in the cycle start_q reaches the cores: they are still idle from the last frame.
  assign done_o = &core_done && !start_q && dispatch_idle && &port_idle && &cache_idle && !(|cache_dirty)
                  && !dram_req_valid_o && !port_rsp_valid;

  always_ff @(posedge clk_i or negedge rst_ni) begin : regs
    if (!rst_ni) begin
      stop_q       <= 1'b0;
      stop_pixel_q <= '0;
      start_q      <= 1'b0;
      frame_q      <= 1'b0;
      launch_q     <= '0;
      tu_cfg_q     <= '0;
    end else begin
      stop_q       <= stop_d;
      stop_pixel_q <= stop_pixel_d;
      start_q      <= start_i;
      frame_q      <= frame_d;
      launch_q     <= launch_i;
      tu_cfg_q     <= tu_cfg_i;
    end
  end

endmodule
