// Testbench for a Yosys netlist of rpu_mem_cosim_top (rtl/flow.py synth --unit mem),
// for Verilator (--binary) or Icarus: replays every cycle of a mem_cosim run on the
// same configuration (mem_cosim --write-vectors) and compares every output bit of the
// netlist with the Verilated RTL's in every cycle. The run's own checks (the data
// oracle, the DRAM's timing) held for the RTL; a netlist that matches it cycle for
// cycle passes them too. The file: a line "<input words> <output words>", then per
// cycle the ports' 32-bit words, least significant first, inputs then outputs, in the
// top's port order (the mem harness's binding, port_words: spec/harnesses.py). Stops at the first mismatch.
//   Vrpu_mem_netlist_tb +vectors=FILE
// The port widths are parameters (flow.py reads them from the netlist and the spec;
// Icarus 11 does not read rpu_pkg.sv).
`timescale 1ns / 1ps
module rpu_mem_netlist_tb #(
  parameter integer Raw          = 1,  // cache ports
  parameter integer InOrder      = 1,  // in-order ports
  parameter integer Caches       = 1,
  parameter integer ReqBits      = 1,  // cache_req
  parameter integer RspBits      = 1,  // cache_rsp
  parameter integer MemReqBits   = 1,
  parameter integer MemRspBits   = 1,
  parameter integer DramReqBits  = 1,
  parameter integer DramRspBits  = 1,
  parameter integer CounterBits  = 1,  // cache_counters
  parameter integer GeometryBits = 1   // cache_geometry
);

  // Each port's words and its first word in the cycle's line.
  localparam integer WRawV  = (Raw + 31) / 32;
  localparam integer WReq   = (Raw * ReqBits + 31) / 32;
  localparam integer WRsp   = (Raw * RspBits + 31) / 32;
  localparam integer WIoV   = (InOrder + 31) / 32;
  localparam integer WMReq  = (InOrder * MemReqBits + 31) / 32;
  localparam integer WMRsp  = (InOrder * MemRspBits + 31) / 32;
  localparam integer WDReq  = (DramReqBits + 31) / 32;
  localparam integer WDRsp  = (DramRspBits + 31) / 32;
  localparam integer WCnt   = (Caches * CounterBits + 31) / 32;
  localparam integer WIdle  = (Caches + 31) / 32;
  localparam integer WGeo   = (Caches * GeometryBits + 31) / 32;

  localparam integer IRst      = 0;
  localparam integer IFlush    = IRst + 1;  // one word: Caches <= 32
  localparam integer IReqValid = IFlush + 1;
  localparam integer IReq      = IReqValid + WRawV;
  localparam integer IRspReady = IReq + WReq;
  localparam integer IMReqValid = IRspReady + WRawV;
  localparam integer IMReq     = IMReqValid + WIoV;
  localparam integer IMRspReady = IMReq + WMReq;
  localparam integer IDReqReady = IMRspReady + WIoV;
  localparam integer IDRspValid = IDReqReady + 1;
  localparam integer IDRsp     = IDRspValid + 1;
  localparam integer InWords   = IDRsp + WDRsp;

  localparam integer OReqReady  = 0;
  localparam integer ORspValid  = OReqReady + WRawV;
  localparam integer ORsp       = ORspValid + WRawV;
  localparam integer OMReqReady = ORsp + WRsp;
  localparam integer OMRspValid = OMReqReady + WIoV;
  localparam integer OMRsp      = OMRspValid + WIoV;
  localparam integer ODReqValid = OMRsp + WMRsp;
  localparam integer ODReq      = ODReqValid + 1;
  localparam integer ODRspReady = ODReq + WDReq;
  localparam integer OCnt       = ODRspReady + 1;
  localparam integer OIdle      = OCnt + WCnt;
  localparam integer ODirty     = OIdle + WIdle;
  localparam integer OGeo       = ODirty + WIdle;
  localparam integer OutWords   = OGeo + WGeo;

  reg clk = 1'b0;
  reg rst_n = 1'b0;

  // The cycle's words as they are read, and the inputs applied: one whole assignment a
  // cycle, since the word-by-word writes did not reach the model's inputs in the
  // Verilated testbench.
  reg  [InWords*32-1:0]  in_flat = '0;
  reg  [InWords*32-1:0]  in_now = '0;
  reg  [OutWords*32-1:0] want = '0;
  wire [OutWords*32-1:0] got;  // every output, each port zero-extended to whole words
  wire [Raw-1:0]                 req_ready, rsp_valid;
  wire [Raw*RspBits-1:0]         rsp;
  wire [InOrder-1:0]             mem_req_ready, mem_rsp_valid;
  wire [InOrder*MemRspBits-1:0]  mem_rsp;
  wire                           dram_req_valid, dram_rsp_ready;
  wire [DramReqBits-1:0]         dram_req;
  wire [Caches*CounterBits-1:0]  counters;
  wire [Caches-1:0]              idle, dirty;
  wire [Caches*GeometryBits-1:0] geometry;
  assign got[OReqReady*32 +: WRawV*32]  = req_ready;
  assign got[ORspValid*32 +: WRawV*32]  = rsp_valid;
  assign got[ORsp*32 +: WRsp*32]        = rsp;
  assign got[OMReqReady*32 +: WIoV*32]  = mem_req_ready;
  assign got[OMRspValid*32 +: WIoV*32]  = mem_rsp_valid;
  assign got[OMRsp*32 +: WMRsp*32]      = mem_rsp;
  assign got[ODReqValid*32 +: 32]       = dram_req_valid;
  assign got[ODReq*32 +: WDReq*32]      = dram_req;
  assign got[ODRspReady*32 +: 32]       = dram_rsp_ready;
  assign got[OCnt*32 +: WCnt*32]        = counters;
  assign got[OIdle*32 +: WIdle*32]      = idle;
  assign got[ODirty*32 +: WIdle*32]     = dirty;
  assign got[OGeo*32 +: WGeo*32]        = geometry;

  rpu_mem_cosim_top dut (
    .clk_i(clk), .rst_ni(rst_n), .flush_i(in_now[IFlush*32 +: Caches]),
    .req_valid_i(in_now[IReqValid*32 +: Raw]), .req_ready_o(req_ready),
    .req_i(in_now[IReq*32 +: Raw*ReqBits]),
    .rsp_valid_o(rsp_valid), .rsp_ready_i(in_now[IRspReady*32 +: Raw]), .rsp_o(rsp),
    .mem_req_valid_i(in_now[IMReqValid*32 +: InOrder]), .mem_req_ready_o(mem_req_ready),
    .mem_req_i(in_now[IMReq*32 +: InOrder*MemReqBits]),
    .mem_rsp_valid_o(mem_rsp_valid), .mem_rsp_ready_i(in_now[IMRspReady*32 +: InOrder]), .mem_rsp_o(mem_rsp),
    .dram_req_valid_o(dram_req_valid), .dram_req_ready_i(in_now[IDReqReady*32]), .dram_req_o(dram_req),
    .dram_rsp_valid_i(in_now[IDRspValid*32]), .dram_rsp_ready_o(dram_rsp_ready),
    .dram_rsp_i(in_now[IDRsp*32 +: DramRspBits]),
    .counters_o(counters), .idle_o(idle), .dirty_o(dirty), .geometry_o(geometry)
  );

  reg [1023:0] path;
  reg [31:0] word;
  integer fd, seed, ok, k, cycle, in_words, out_words;

  `include "rpu_netlist_vectors.svh"

  initial begin
    open_vectors(path, fd, seed);
    ok = $fscanf(fd, "%d %d\n", in_words, out_words);
    if (ok != 2 || in_words != InWords || out_words != OutWords) begin
      $display("netlist FAIL: %0s has %0d input and %0d output words a cycle; this netlist's ports take %0d and %0d",
               path, in_words, out_words, InWords, OutWords);
      $fatal(2);
    end
    // Reset as the harness does (every input low), then its cycles.
    reset_dut();
    cycle = 0;
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
            $display("netlist FAIL: cycle %0d: output word %0d is %h, the RTL's was %h (ports in the order of %0s)",
                     cycle, k, got[k*32 +: 32], want[k*32 +: 32], "the mem harness's port_words");
          end
        end
        $fatal(1);
      end
      clk = 1'b1;
      #1 clk = 1'b0;
      cycle = cycle + 1;
      ok = $fscanf(fd, "%h", word);
    end
    $fclose(fd);
    $display("netlist ok: %0d cycles match the RTL", cycle);
    $finish;
  end

endmodule
