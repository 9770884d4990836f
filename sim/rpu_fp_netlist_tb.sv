// Testbench for a Yosys netlist of rpu_fp_cosim_top (rtl/flow.py synth), for Verilator
// (--binary, the default) or Icarus: reads
// the vectors and soft-model results that fp_cosim --write-vectors wrote, drives them
// through the valid/ready port with random stalls, and compares every response with
// the model's result and tag. Stops at the first mismatch with the vector, operands,
// both results and the cycle.
//   Vrpu_fp_netlist_tb +vectors=FILE [+seed=N]   or   vvp tb.vvp +vectors=FILE [+seed=N]
// Icarus 11 does not read rpu_pkg.sv (`int unsigned` localparams), so flow.py passes
// the port widths from the spec as parameters.
`timescale 1ns / 1ps
module rpu_fp_netlist_tb #(
  parameter integer OpBits = 1,
  parameter integer TagBits = 1
);

  localparam integer MaxVectors = 1 << 18;
  localparam integer StallPercent = 6;
  localparam integer Timeout = 1000;

  reg                               clk = 1'b0;
  reg                               rst_n = 1'b0;
  reg                               req_valid = 1'b0;
  wire                              req_ready;
  reg  [OpBits-1:0]      req_op = '0;
  reg  [TagBits-1:0]     req_tag = '0;
  reg  [31:0]                       req_a = '0, req_b = '0, req_c = '0;
  wire                              rsp_valid;
  reg                               rsp_ready = 1'b0;
  wire [TagBits-1:0]     rsp_tag;
  wire [31:0]                       rsp_result;

  rpu_fp_cosim_top dut (
    .clk_i(clk), .rst_ni(rst_n),
    .req_valid_i(req_valid), .req_ready_o(req_ready), .req_op_i(req_op), .req_tag_i(req_tag),
    .req_a_i(req_a), .req_b_i(req_b), .req_c_i(req_c),
    .rsp_valid_o(rsp_valid), .rsp_ready_i(rsp_ready), .rsp_tag_o(rsp_tag), .rsp_result_o(rsp_result)
  );

  reg [31:0] va [0:MaxVectors-1];
  reg [31:0] vb [0:MaxVectors-1];
  reg [31:0] vc [0:MaxVectors-1];
  reg [31:0] ve [0:MaxVectors-1];

  reg [1023:0] path;
  integer fd, n, i, sent, got, cycle, last, seed, ok;
  reg [31:0] op;
  reg        fire_req;

  `include "rpu_netlist_vectors.svh"

  initial begin
    open_vectors(path, fd, seed);
    ok = $fscanf(fd, "%h %d\n", op, n);
    if (ok != 2 || n > MaxVectors) begin
      $display("netlist FAIL: bad header in %0s (or more than %0d vectors)", path, MaxVectors);
      $fatal(2);
    end
    for (i = 0; i < n; i = i + 1) begin
      ok = $fscanf(fd, "%h %h %h %h\n", va[i], vb[i], vc[i], ve[i]);
      if (ok != 4) begin
        $display("netlist FAIL: %0s: vector %0d unreadable", path, i);
        $fatal(2);
      end
    end
    $fclose(fd);

    req_op = op[OpBits-1:0];
    reset_dut();

    sent = 0;
    got = 0;
    last = 0;
    for (cycle = 0; got < n; cycle = cycle + 1) begin
      req_valid = sent < n && ({$random(seed)} % 100) >= StallPercent;
      rsp_ready = ({$random(seed)} % 100) >= StallPercent;
      if (sent < n) begin
        req_a = va[sent];
        req_b = vb[sent];
        req_c = vc[sent];
        req_tag = sent[TagBits-1:0];
      end
      #1;
      if (rsp_valid && rsp_ready) begin
        if (rsp_result !== ve[got] || rsp_tag !== got[TagBits-1:0]) begin
          $display("netlist FAIL: op %0d, cycle %0d, vector %0d: a = %h b = %h c = %h expected %h tag %h actual %h tag %h",
                   op, cycle, got, va[got], vb[got], vc[got], ve[got], got[TagBits-1:0],
                   rsp_result, rsp_tag);
          $fatal(1);
        end
        got = got + 1;
        last = cycle;
      end
      fire_req = req_valid && req_ready;
      if (fire_req) sent = sent + 1;
      if (sent == got) last = cycle;
      if (cycle - last > Timeout) begin
        $display("netlist FAIL: op %0d: no response for %0d cycles at cycle %0d (vector %0d)", op, Timeout, cycle, got);
        $fatal(1);
      end
      clk = 1'b1;
      #1 clk = 1'b0;
    end
    $display("netlist ok: op %0d: %0d vectors match the model in %0d cycles", op, n, cycle);
    $finish;
  end

endmodule
