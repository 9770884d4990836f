// One shader core as the Verilator harness drives it (sim/spu_cosim.cpp), each stream
// one flat port of its rpu_pkg width (spec/streams.toml): core 0 of a chip of one core,
// its memory port and ray port answered by the harness, its trace ports read by the
// lockstep checker. Only wiring.
module rpu_spu_cosim_top #(
  parameter int unsigned Threads    = rpu_pkg::ConfigTinyThreadsPerCore,
  parameter int unsigned ChunkSize  = rpu_pkg::ConfigTinyChunkSize,
  parameter int unsigned Registers  = rpu_pkg::ConfigTinyRegisters,
  parameter int unsigned CallDepth  = rpu_pkg::ConfigTinyCallDepth,
  parameter int unsigned StackBytes = rpu_pkg::ConfigTinyStackBytes,
  parameter int unsigned SfuUnits   = rpu_pkg::ConfigTinySfuUnits,
  parameter int unsigned CodeWords  = 4096,
  parameter int unsigned ExpBits    = rpu_pkg::FormatFp32ExponentBits,
  parameter int unsigned FracBits   = rpu_pkg::FormatFp32FractionBits,
  localparam int unsigned CodeAddrBits = $clog2(CodeWords)
) (
  input  logic                               clk_i,
  input  logic                               rst_ni,

  input  logic                               code_we_i,
  input  logic [CodeAddrBits-1:0]            code_addr_i,
  input  logic [63:0]                        code_data_i,

  input  logic                               start_i,
  input  logic [rpu_pkg::LaunchBits-1:0]     launch_i,
  input  logic                               stop_i,
  input  logic [31:0]                        stop_pixel_i,
  output logic                               done_o,

  output logic                               cache_req_valid_o,
  input  logic                               cache_req_ready_i,
  output logic [rpu_pkg::CacheReqBits-1:0]   cache_req_o,
  input  logic                               cache_rsp_valid_i,
  output logic                               cache_rsp_ready_o,
  input  logic [rpu_pkg::CacheRspBits-1:0]   cache_rsp_i,

  output logic                               trace_req_valid_o,
  input  logic                               trace_req_ready_i,
  output logic [rpu_pkg::TraceReqBits-1:0]   trace_req_o,
  input  logic                               trace_rsp_valid_i,
  output logic                               trace_rsp_ready_o,
  input  logic [rpu_pkg::TraceRspBits-1:0]   trace_rsp_i,

  output logic                               issue_valid_o,
  output logic [rpu_pkg::IssueBits-1:0]      issue_o,
  output logic                               retire_valid_o,
  output logic [rpu_pkg::RetireBits-1:0]     retire_o,
  output logic                               wb_valid_o,
  output logic [rpu_pkg::WritebackBits-1:0]  wb_o,
  output logic                               fault_valid_o,
  output logic [rpu_pkg::FaultBits-1:0]      fault_o
);

  rpu_pkg::launch_t    launch;
  rpu_pkg::cache_req_t cache_req;
  rpu_pkg::cache_rsp_t cache_rsp;
  rpu_pkg::trace_req_t trace_req;
  rpu_pkg::trace_rsp_t trace_rsp;
  rpu_pkg::issue_t     issue;
  rpu_pkg::retire_t    retire;
  rpu_pkg::writeback_t wb;
  rpu_pkg::fault_t     fault;

  assign launch      = launch_i;
  assign cache_rsp   = cache_rsp_i;
  assign trace_rsp   = trace_rsp_i;
  assign cache_req_o = cache_req;
  assign trace_req_o = trace_req;
  assign issue_o     = issue;
  assign retire_o    = retire;
  assign wb_o        = wb;
  assign fault_o     = fault;

  // The counters are the chip's (sim/chip_cosim reads them); a core alone has no frame.
  rpu_pkg::core_counters_t counters;

  rpu_spu #(
    .CoreId(0), .Cores(1), .Threads(Threads), .ChunkSize(ChunkSize), .Registers(Registers),
    .CallDepth(CallDepth), .StackBytes(StackBytes), .SfuUnits(SfuUnits), .CodeWords(CodeWords),
    .ExpBits(ExpBits), .FracBits(FracBits)
  ) u_spu (
    .clk_i, .rst_ni,
    .code_we_i, .code_addr_i, .code_data_i,
    .start_i, .launch_i(launch), .stop_i, .stop_pixel_i, .done_o,
    .cache_req_valid_o, .cache_req_ready_i, .cache_req_o(cache_req),
    .cache_rsp_valid_i, .cache_rsp_ready_o, .cache_rsp_i(cache_rsp),
    .trace_req_valid_o, .trace_req_ready_i, .trace_req_o(trace_req),
    .trace_rsp_valid_i, .trace_rsp_ready_o, .trace_rsp_i(trace_rsp),
    .issue_valid_o, .issue_o(issue), .retire_valid_o, .retire_o(retire),
    .wb_valid_o, .wb_o(wb), .fault_valid_o, .fault_o(fault),
    .count_i(1'b1), .counters_o(counters)
  );
  logic unused_counters;
  assign unused_counters = ^counters;

endmodule
