// The chip as the Verilator harness and the rtl backend drive it (sim/chip_run.cpp),
// each single stream one flat port of its rpu_pkg width (spec/streams.toml); the cores'
// trace ports are rpu_top's, already flat. Only wiring.
module rpu_chip_cosim_top #(
  parameter int unsigned Cores                   = rpu_pkg::ConfigTinyShaderCores,
  parameter int unsigned Threads                 = rpu_pkg::ConfigTinyThreadsPerCore,
  parameter int unsigned ChunkSize               = rpu_pkg::ConfigTinyChunkSize,
  parameter int unsigned Registers               = rpu_pkg::ConfigTinyRegisters,
  parameter int unsigned CallDepth               = rpu_pkg::ConfigTinyCallDepth,
  parameter int unsigned StackBytes              = rpu_pkg::ConfigTinyStackBytes,
  parameter int unsigned SfuUnits                = rpu_pkg::ConfigTinySfuUnits,
  parameter int unsigned StackDepth              = rpu_pkg::ConfigTinyStackDepth,
  parameter int unsigned RayUnits                = rpu_pkg::ConfigTinyTraversalUnits,
  parameter int unsigned TuSlots                 = rpu_pkg::ConfigTinyTuSlots,
  parameter int unsigned TuPipe                  = rpu_pkg::ConfigTinyTuPipe,
  parameter int unsigned TuSetups                = rpu_pkg::ConfigTinyTuSetups,
  parameter int unsigned IsectMode               = rpu_pkg::IsectModeWoop,
  parameter int unsigned NodeBytes          = rpu_pkg::ConfigTinyNodeCacheBytes,
  parameter int unsigned NodeWays           = rpu_pkg::ConfigTinyNodeCacheWays,
  parameter int unsigned NodeHitLatency     = rpu_pkg::ConfigTinyNodeCacheHitLatency,
  parameter int unsigned NodeMshrs          = rpu_pkg::ConfigTinyNodeCacheMshrs,
  parameter int unsigned TriangleBytes      = rpu_pkg::ConfigTinyTriangleCacheBytes,
  parameter int unsigned TriangleWays       = rpu_pkg::ConfigTinyTriangleCacheWays,
  parameter int unsigned TriangleHitLatency = rpu_pkg::ConfigTinyTriangleCacheHitLatency,
  parameter int unsigned TriangleMshrs      = rpu_pkg::ConfigTinyTriangleCacheMshrs,
  parameter int unsigned DataBytes          = rpu_pkg::ConfigTinyDataCacheBytes,
  parameter int unsigned DataWays           = rpu_pkg::ConfigTinyDataCacheWays,
  parameter int unsigned DataHitLatency     = rpu_pkg::ConfigTinyDataCacheHitLatency,
  parameter int unsigned DataMshrs          = rpu_pkg::ConfigTinyDataCacheMshrs,
  parameter int unsigned CodeWords               = 4096,
  parameter int unsigned ExpBits                 = rpu_pkg::FormatFp32ExponentBits,
  parameter int unsigned FracBits                = rpu_pkg::FormatFp32FractionBits,
  localparam int unsigned CodeAddrBits = $clog2(CodeWords)
) (
  input  logic                                    clk_i,
  input  logic                                    rst_ni,

  input  logic                                    code_we_i,
  input  logic [CodeAddrBits-1:0]                 code_addr_i,
  input  logic [63:0]                             code_data_i,

  input  logic                                    start_i,
  input  logic [rpu_pkg::LaunchBits-1:0]          launch_i,
  input  logic [rpu_pkg::TuCfgBits-1:0]           tu_cfg_i,
  output logic                                    done_o,

  output logic                                    dram_req_valid_o,
  input  logic                                    dram_req_ready_i,
  output logic [rpu_pkg::DramReqBits-1:0]         dram_req_o,
  input  logic                                    dram_rsp_valid_i,
  output logic                                    dram_rsp_ready_o,
  input  logic [rpu_pkg::DramRspBits-1:0]         dram_rsp_i,

  output logic [Cores-1:0]                        issue_valid_o,
  output logic [Cores*rpu_pkg::IssueBits-1:0]     issue_o,
  output logic [Cores-1:0]                        retire_valid_o,
  output logic [Cores*rpu_pkg::RetireBits-1:0]    retire_o,
  output logic [Cores-1:0]                        wb_valid_o,
  output logic [Cores*rpu_pkg::WritebackBits-1:0] wb_o,
  output logic [Cores-1:0]                        fault_valid_o,
  output logic [Cores*rpu_pkg::FaultBits-1:0]     fault_o,

  output logic [Cores*rpu_pkg::CoreCountersBits-1:0]        core_counters_o,
  output logic [RayUnits*rpu_pkg::RayUnitCountersBits-1:0]  ray_counters_o,
  output logic [(2+Cores)*rpu_pkg::CacheCountersBits-1:0]   cache_counters_o
);

  rpu_pkg::launch_t   launch;
  rpu_pkg::tu_cfg_t   tu_cfg;
  rpu_pkg::dram_req_t dram_req;
  rpu_pkg::dram_rsp_t dram_rsp;

  assign launch     = launch_i;
  assign tu_cfg     = tu_cfg_i;
  assign dram_rsp   = dram_rsp_i;
  assign dram_req_o = dram_req;

  rpu_top #(
    .Cores(Cores), .Threads(Threads), .ChunkSize(ChunkSize), .Registers(Registers), .CallDepth(CallDepth),
    .StackBytes(StackBytes), .SfuUnits(SfuUnits), .StackDepth(StackDepth), .RayUnits(RayUnits),
    .TuSlots(TuSlots), .TuPipe(TuPipe), .TuSetups(TuSetups), .IsectMode(IsectMode),
    .NodeBytes(NodeBytes), .NodeWays(NodeWays), .NodeHitLatency(NodeHitLatency),
    .NodeMshrs(NodeMshrs),
    .TriangleBytes(TriangleBytes), .TriangleWays(TriangleWays),
    .TriangleHitLatency(TriangleHitLatency), .TriangleMshrs(TriangleMshrs),
    .DataBytes(DataBytes), .DataWays(DataWays), .DataHitLatency(DataHitLatency),
    .DataMshrs(DataMshrs),
    .CodeWords(CodeWords), .ExpBits(ExpBits), .FracBits(FracBits)
  ) u_top (
    .clk_i, .rst_ni,
    .code_we_i, .code_addr_i, .code_data_i,
    .start_i, .launch_i(launch), .tu_cfg_i(tu_cfg), .done_o,
    .dram_req_valid_o, .dram_req_ready_i, .dram_req_o(dram_req),
    .dram_rsp_valid_i, .dram_rsp_ready_o, .dram_rsp_i(dram_rsp),
    .issue_valid_o, .issue_o, .retire_valid_o, .retire_o, .wb_valid_o, .wb_o, .fault_valid_o, .fault_o,
    .core_counters_o, .ray_counters_o, .cache_counters_o
  );

endmodule
