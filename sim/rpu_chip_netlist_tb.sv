// Testbench for a Yosys netlist of rpu_chip_cosim_top (rtl/flow.py synth --unit chip),
// for Verilator (--binary) or Icarus: replays every cycle of a chip_cosim frame on the
// same configuration (chip_cosim --write-vectors: the code writes, start and the frame
// to the memory's last write) and compares every output bit of the netlist with the
// Verilated RTL's in every cycle. The framebuffer leaves the chip as memory-port
// writes, so a netlist that matches every output in every cycle renders the RTL's frame;
// with +requests=FILE the netlist's own memory-port requests are also written there (one
// line each, its words least significant first) for flow.py to rebuild the frame from.
// The vector file: a line "<input words> <output words>", then per cycle the ports'
// 32-bit words, least significant first, inputs then outputs, in the top's port order
// (the chip harness's binding, port_words: spec/harnesses.py). Stops at the first mismatch with the cycle, the
// port and its words.
//   Vrpu_chip_netlist_tb +vectors=FILE [+requests=FILE]
// The port widths are parameters (flow.py reads them from the netlist and the spec;
// Icarus 11 does not read rpu_pkg.sv).
`timescale 1ns / 1ps
module rpu_chip_netlist_tb #(
  parameter integer Cores               = 1,
  parameter integer Ways                = 1,  // retire and writeback records: Cores x IssueLanes
  parameter integer RayUnits            = 1,
  parameter integer Caches              = 3,  // the node and triangle caches and the data caches
  parameter integer CodeAddrBits        = 1,
  parameter integer LaunchBits          = 1,
  parameter integer TuCfgBits           = 1,
  parameter integer DramReqBits         = 1,
  parameter integer DramRspBits         = 1,
  parameter integer IssueBits           = 1,
  parameter integer RetireBits          = 1,
  parameter integer WritebackBits       = 1,
  parameter integer FaultBits           = 1,
  parameter integer CoreCountersBits    = 1,
  parameter integer RayUnitCountersBits = 1,
  parameter integer CacheCountersBits   = 1
);

  // Each port's words and its first word in the cycle's line.
  localparam integer WCores    = (Cores + 31) / 32;
  localparam integer WWays     = (Ways + 31) / 32;
  localparam integer WLaunch   = (LaunchBits + 31) / 32;
  localparam integer WTuCfg    = (TuCfgBits + 31) / 32;
  localparam integer WDReq     = (DramReqBits + 31) / 32;
  localparam integer WDRsp     = (DramRspBits + 31) / 32;
  localparam integer WIssue    = (Cores * IssueBits + 31) / 32;
  localparam integer WRetire   = (Ways * RetireBits + 31) / 32;
  localparam integer WWb       = (Ways * WritebackBits + 31) / 32;
  localparam integer WFault    = (Cores * FaultBits + 31) / 32;
  localparam integer WCoreCnt  = (Cores * CoreCountersBits + 31) / 32;
  localparam integer WRayCnt   = (RayUnits * RayUnitCountersBits + 31) / 32;
  localparam integer WCacheCnt = (Caches * CacheCountersBits + 31) / 32;

  localparam integer IRst       = 0;
  localparam integer ICodeWe    = IRst + 1;
  localparam integer ICodeAddr  = ICodeWe + 1;
  localparam integer ICodeData  = ICodeAddr + 1;
  localparam integer IStart     = ICodeData + 2;
  localparam integer ILaunch    = IStart + 1;
  localparam integer ITuCfg     = ILaunch + WLaunch;
  localparam integer IDReqReady = ITuCfg + WTuCfg;
  localparam integer IDRspValid = IDReqReady + 1;
  localparam integer IDRsp      = IDRspValid + 1;
  localparam integer InWords    = IDRsp + WDRsp;

  localparam integer ODone        = 0;
  localparam integer ODReqValid   = ODone + 1;
  localparam integer ODReq        = ODReqValid + 1;
  localparam integer ODRspReady   = ODReq + WDReq;
  localparam integer OIssueValid  = ODRspReady + 1;
  localparam integer OIssue       = OIssueValid + WCores;
  localparam integer ORetireValid = OIssue + WIssue;
  localparam integer ORetire      = ORetireValid + WWays;
  localparam integer OWbValid     = ORetire + WRetire;
  localparam integer OWb          = OWbValid + WWays;
  localparam integer OFaultValid  = OWb + WWb;
  localparam integer OFault       = OFaultValid + WCores;
  localparam integer OCoreCnt     = OFault + WFault;
  localparam integer ORayCnt      = OCoreCnt + WCoreCnt;
  localparam integer OCacheCnt    = ORayCnt + WRayCnt;
  localparam integer OutWords     = OCacheCnt + WCacheCnt;

  reg clk = 1'b0;
  reg rst_n = 1'b0;

  // The cycle's words as they are read, and the inputs applied: one whole assignment a
  // cycle, since word-by-word writes did not reach the model's inputs in the Verilated
  // mem testbench (sim/rpu_mem_netlist_tb.sv).
  reg  [InWords*32-1:0]  in_flat = '0;
  reg  [InWords*32-1:0]  in_now = '0;
  reg  [OutWords*32-1:0] want = '0;
  wire [OutWords*32-1:0] got;  // every output, each port zero-extended to whole words
  wire                               done, dram_req_valid, dram_rsp_ready;
  wire [DramReqBits-1:0]             dram_req;
  wire [Cores-1:0]                   issue_valid, fault_valid;
  wire [Ways-1:0]                    retire_valid, wb_valid;
  wire [Cores*IssueBits-1:0]         issue;
  wire [Ways*RetireBits-1:0]         retire;
  wire [Ways*WritebackBits-1:0]      wb;
  wire [Cores*FaultBits-1:0]         fault;
  wire [Cores*CoreCountersBits-1:0]  core_counters;
  wire [RayUnits*RayUnitCountersBits-1:0] ray_counters;
  wire [Caches*CacheCountersBits-1:0]     cache_counters;
  assign got[ODone*32 +: 32]                 = done;
  assign got[ODReqValid*32 +: 32]            = dram_req_valid;
  assign got[ODReq*32 +: WDReq*32]           = dram_req;
  assign got[ODRspReady*32 +: 32]            = dram_rsp_ready;
  assign got[OIssueValid*32 +: WCores*32]    = issue_valid;
  assign got[OIssue*32 +: WIssue*32]         = issue;
  assign got[ORetireValid*32 +: WWays*32]    = retire_valid;
  assign got[ORetire*32 +: WRetire*32]       = retire;
  assign got[OWbValid*32 +: WWays*32]        = wb_valid;
  assign got[OWb*32 +: WWb*32]               = wb;
  assign got[OFaultValid*32 +: WCores*32]    = fault_valid;
  assign got[OFault*32 +: WFault*32]         = fault;
  assign got[OCoreCnt*32 +: WCoreCnt*32]     = core_counters;
  assign got[ORayCnt*32 +: WRayCnt*32]       = ray_counters;
  assign got[OCacheCnt*32 +: WCacheCnt*32]   = cache_counters;

  rpu_chip_cosim_top dut (
    .clk_i(clk), .rst_ni(rst_n),
    .code_we_i(in_now[ICodeWe*32]), .code_addr_i(in_now[ICodeAddr*32 +: CodeAddrBits]),
    .code_data_i(in_now[ICodeData*32 +: 64]),
    .start_i(in_now[IStart*32]), .launch_i(in_now[ILaunch*32 +: LaunchBits]),
    .tu_cfg_i(in_now[ITuCfg*32 +: TuCfgBits]), .done_o(done),
    .dram_req_valid_o(dram_req_valid), .dram_req_ready_i(in_now[IDReqReady*32]), .dram_req_o(dram_req),
    .dram_rsp_valid_i(in_now[IDRspValid*32]), .dram_rsp_ready_o(dram_rsp_ready),
    .dram_rsp_i(in_now[IDRsp*32 +: DramRspBits]),
    .issue_valid_o(issue_valid), .issue_o(issue), .retire_valid_o(retire_valid), .retire_o(retire),
    .wb_valid_o(wb_valid), .wb_o(wb), .fault_valid_o(fault_valid), .fault_o(fault),
    .core_counters_o(core_counters), .ray_counters_o(ray_counters), .cache_counters_o(cache_counters)
  );

  // The output port holding word k of a cycle's outputs, and its first word.
  function automatic [8*16-1:0] port_of(input integer k);
    port_of = k >= OCacheCnt    ? "cache_counters_o" : k >= ORayCnt     ? "ray_counters_o" :
              k >= OCoreCnt     ? "core_counters_o"  : k >= OFault      ? "fault_o" :
              k >= OFaultValid  ? "fault_valid_o"    : k >= OWb         ? "wb_o" :
              k >= OWbValid     ? "wb_valid_o"       : k >= ORetire     ? "retire_o" :
              k >= ORetireValid ? "retire_valid_o"   : k >= OIssue      ? "issue_o" :
              k >= OIssueValid  ? "issue_valid_o"    : k >= ODRspReady  ? "dram_rsp_ready_o" :
              k >= ODReq        ? "dram_req_o"       : k >= ODReqValid  ? "dram_req_valid_o" : "done_o";
  endfunction
  function automatic integer first_word(input integer k);
    first_word = k >= OCacheCnt    ? OCacheCnt    : k >= ORayCnt     ? ORayCnt :
                 k >= OCoreCnt     ? OCoreCnt     : k >= OFault      ? OFault :
                 k >= OFaultValid  ? OFaultValid  : k >= OWb         ? OWb :
                 k >= OWbValid     ? OWbValid     : k >= ORetire     ? ORetire :
                 k >= ORetireValid ? ORetireValid : k >= OIssue      ? OIssue :
                 k >= OIssueValid  ? OIssueValid  : k >= ODRspReady  ? ODRspReady :
                 k >= ODReq        ? ODReq        : k >= ODReqValid  ? ODReqValid : ODone;
  endfunction

  reg [1023:0] path, requests_path;
  reg [31:0] word;
  integer fd, wfd, seed, ok, k, cycle, in_words, out_words, requests;

  `include "rpu_netlist_vectors.svh"

  initial begin
    open_vectors(path, fd, seed);
    wfd = 0;
    if ($value$plusargs("requests=%s", requests_path)) begin
      wfd = $fopen(requests_path, "w");
      if (wfd == 0) begin
        $display("netlist FAIL: cannot write %0s", requests_path);
        $fatal(2);
      end
    end
    ok = $fscanf(fd, "%d %d\n", in_words, out_words);
    if (ok != 2 || in_words != InWords || out_words != OutWords) begin
      $display("netlist FAIL: %0s has %0d input and %0d output words a cycle; this netlist's ports take %0d and %0d",
               path, in_words, out_words, InWords, OutWords);
      $fatal(2);
    end
    // Reset with every input low (the harness's reset cycles are not in the file), then
    // its cycles.
    reset_dut();
    cycle = 0;
    requests = 0;
    ok = $fscanf(fd, "%h", word);
    while (ok == 1) begin
      in_flat[0 +: 32] = word;
      for (k = 1; k < InWords; k = k + 1) begin
        ok = $fscanf(fd, "%h", word);
        in_flat[k*32 +: 32] = word;
      end
      for (k = 0; k < OutWords; k = k + 1) begin
        ok = $fscanf(fd, "%h", word);
        want[k*32 +: 32] = word;
      end
      if (ok != 1) begin
        $display("netlist FAIL: %0s: cycle %0d is cut short", path, cycle);
        $fatal(2);
      end
      in_now = in_flat;
      rst_n = in_now[IRst*32];
      #1;
      if (got !== want) begin
        for (k = 0; k < OutWords; k = k + 1) begin
          if (got[k*32 +: 32] !== want[k*32 +: 32]) begin
            $display("netlist FAIL: cycle %0d (the file's, from the first out of reset): %0s word %0d is %h, %s%h",
                     cycle, port_of(k), k - first_word(k), got[k*32 +: 32], "the RTL's was ", want[k*32 +: 32]);
          end
        end
        $fatal(1);
      end
      if (wfd != 0 && dram_req_valid && in_now[IDReqReady*32]) begin
        for (k = 0; k < WDReq; k = k + 1) $fwrite(wfd, "%h ", got[(ODReq + k)*32 +: 32]);
        $fwrite(wfd, "\n");
        requests = requests + 1;
      end
      clk = 1'b1;
      #1 clk = 1'b0;
      cycle = cycle + 1;
      ok = $fscanf(fd, "%h", word);
    end
    $fclose(fd);
    if (wfd != 0) $fclose(wfd);
    $display("netlist ok: %0d cycles match the RTL (%0d memory-port requests)", cycle, requests);
    $finish;
  end

endmodule
