// Testbench for a Yosys netlist of a unit with one request and one response stream in
// order (rpu_fp_unit_cosim_top, rpu_iu_cosim_top; rtl/flow.py synth), for Verilator (--binary,
// the default) or Icarus: reads the request and expected response words that the unit's
// harness wrote (fp_cosim, iu_cosim --write-vectors), drives the requests through the
// valid/ready port with random stalls, and compares every response with the model's,
// whole. It knows no field of either stream (spec/streams.toml): a mismatch prints both
// responses in hex, most significant word first, as docs/streams.md lays them out. Stops
// at the first mismatch with the vector, its request and the cycle.
//   Vrpu_stream_netlist_tb +vectors=FILE [+seed=N]   or   vvp tb.vvp +vectors=FILE [+seed=N]
// The netlist's top is `RPU_STREAM_DUT, a macro flow.py defines: a module name cannot be a
// parameter. Icarus 11 does not read rpu_pkg.sv (`int unsigned` localparams), so flow.py
// passes the stream widths from the spec as parameters.
`ifndef RPU_STREAM_DUT
  `error "define RPU_STREAM_DUT as the netlist's top module"
`endif
`timescale 1ns / 1ps
module rpu_stream_netlist_tb #(
  parameter integer ReqBits = 1,
  parameter integer RspBits = 1
);

  localparam integer MaxVectors = 1 << 18;
  localparam integer StallPercent = 6;
  localparam integer Timeout = 1000;
  localparam integer ReqWords = (ReqBits + 31) / 32;
  localparam integer RspWords = (RspBits + 31) / 32;

  reg                clk = 1'b0;
  reg                rst_n = 1'b0;
  reg                req_valid = 1'b0;
  wire               req_ready;
  reg  [ReqBits-1:0] req = '0;
  wire               rsp_valid;
  reg                rsp_ready = 1'b0;
  wire [RspBits-1:0] rsp;

  `RPU_STREAM_DUT dut (
    .clk_i(clk), .rst_ni(rst_n),
    .req_valid_i(req_valid), .req_ready_o(req_ready), .req_i(req),
    .rsp_valid_o(rsp_valid), .rsp_ready_i(rsp_ready), .rsp_o(rsp)
  );

  reg [31:0] req_words [0:MaxVectors*ReqWords-1];
  reg [31:0] rsp_words [0:MaxVectors*RspWords-1];
  reg [ReqWords*32-1:0] req_flat;
  reg [RspWords*32-1:0] want_flat;

  reg [1023:0] path;
  integer fd, n, i, k, sent, got, cycle, last, seed, ok;
  reg        fire_req;

  `include "rpu_netlist_vectors.svh"

  initial begin
    open_vectors(path, fd, seed);
    ok = $fscanf(fd, "%d\n", n);
    if (ok != 1 || n > MaxVectors) begin
      $display("netlist FAIL: bad header in %0s (or more than %0d vectors)", path, MaxVectors);
      $fatal(2);
    end
    for (i = 0; i < n; i = i + 1) begin
      ok = 0;
      for (k = 0; k < ReqWords; k = k + 1) ok = ok + $fscanf(fd, "%h", req_words[i * ReqWords + k]);
      for (k = 0; k < RspWords; k = k + 1) ok = ok + $fscanf(fd, "%h", rsp_words[i * RspWords + k]);
      if (ok != ReqWords + RspWords) begin
        $display("netlist FAIL: %0s: vector %0d unreadable", path, i);
        $fatal(2);
      end
    end
    $fclose(fd);

    reset_dut();

    sent = 0;
    got = 0;
    last = 0;
    for (cycle = 0; got < n; cycle = cycle + 1) begin
      req_valid = sent < n && ({$random(seed)} % 100) >= StallPercent;
      rsp_ready = ({$random(seed)} % 100) >= StallPercent;
      if (sent < n) begin
        for (k = 0; k < ReqWords; k = k + 1) req_flat[k*32 +: 32] = req_words[sent * ReqWords + k];
        req = req_flat[ReqBits-1:0];
      end
      #1;
      if (rsp_valid && rsp_ready) begin
        for (k = 0; k < RspWords; k = k + 1) want_flat[k*32 +: 32] = rsp_words[got * RspWords + k];
        if (rsp !== want_flat[RspBits-1:0]) begin
          for (k = 0; k < ReqWords; k = k + 1) req_flat[k*32 +: 32] = req_words[got * ReqWords + k];
          $display("netlist FAIL: cycle %0d, vector %0d: request %h", cycle, got, req_flat[ReqBits-1:0]);
          $display("  expected response %h; actual %h", want_flat[RspBits-1:0], rsp);
          $fatal(1);
        end
        got = got + 1;
        last = cycle;
      end
      fire_req = req_valid && req_ready;
      if (fire_req) sent = sent + 1;
      if (sent == got) last = cycle;
      if (cycle - last > Timeout) begin
        $display("netlist FAIL: no response for %0d cycles at cycle %0d (vector %0d)", Timeout, cycle, got);
        $fatal(1);
      end
      clk = 1'b1;
      #1 clk = 1'b0;
    end
    $display("netlist ok: %0d vectors match the model in %0d cycles", n, cycle);
    $finish;
  end

endmodule
