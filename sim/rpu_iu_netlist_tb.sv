// Testbench for a Yosys netlist of rpu_iu_cosim_top (rtl/flow.py synth --unit iu): reads
// the IU tests and functional-model results that iu_cosim --write-vectors wrote, drives
// them through the valid/ready port with random stalls, and compares every response
// (tag, hit, t, u, v) with the model's. Stops at the first mismatch with the test's
// index, its inputs, both outputs and the cycle.
//   Vrpu_iu_netlist_tb +vectors=FILE [+seed=N]
`timescale 1ns / 1ps
module rpu_iu_netlist_tb;

  localparam integer MaxVectors = 1 << 16;
  localparam integer Fields = 29;  // 25 input words, then hit, t, u, v
  localparam integer StallPercent = 6;
  localparam integer Timeout = 1000;

  reg          clk = 1'b0;
  reg          rst_n = 1'b0;
  reg          req_valid = 1'b0;
  wire         req_ready;
  reg  [7:0]   req_tag = '0;
  reg  [95:0]  req_origin = '0, req_direction = '0;
  reg  [31:0]  req_t_min = '0, req_t_best = '0;
  reg  [1:0]   req_kx = '0, req_ky = '0, req_kz = '0;
  reg  [31:0]  req_shear_x = '0, req_shear_y = '0;
  reg  [383:0] req_record = '0;
  wire         rsp_valid;
  reg          rsp_ready = 1'b0;
  wire [7:0]   rsp_tag;
  wire         rsp_hit;
  wire [31:0]  rsp_t, rsp_u, rsp_v;

  rpu_iu_cosim_top dut (
    .clk_i(clk), .rst_ni(rst_n),
    .req_valid_i(req_valid), .req_ready_o(req_ready), .req_tag_i(req_tag),
    .req_origin_i(req_origin), .req_direction_i(req_direction), .req_t_min_i(req_t_min),
    .req_t_best_i(req_t_best), .req_kx_i(req_kx), .req_ky_i(req_ky), .req_kz_i(req_kz),
    .req_shear_x_i(req_shear_x), .req_shear_y_i(req_shear_y),
    .req_record_i(req_record),
    .rsp_valid_o(rsp_valid), .rsp_ready_i(rsp_ready), .rsp_tag_o(rsp_tag), .rsp_hit_o(rsp_hit),
    .rsp_t_o(rsp_t), .rsp_u_o(rsp_u), .rsp_v_o(rsp_v)
  );

  reg [31:0] vec [0:MaxVectors*Fields-1];

  reg [1023:0] path;
  integer fd, n, i, k, sent, got, cycle, last, seed, ok;

  `include "rpu_netlist_vectors.svh"

  initial begin
    open_vectors(path, fd, seed);
    ok = $fscanf(fd, "%d\n", n);
    if (ok != 1 || n > MaxVectors) begin
      $display("netlist FAIL: bad header in %0s (or more than %0d vectors)", path, MaxVectors);
      $fatal(2);
    end
    for (i = 0; i < n * Fields; i = i + 1) begin
      ok = $fscanf(fd, "%h", vec[i]);
      if (ok != 1) begin
        $display("netlist FAIL: %0s: word %0d unreadable", path, i);
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
        k = sent * Fields;
        req_origin    = {vec[k + 2], vec[k + 1], vec[k]};
        req_direction = {vec[k + 5], vec[k + 4], vec[k + 3]};
        req_t_min     = vec[k + 6];
        req_t_best    = vec[k + 7];
        req_kx        = vec[k + 8][1:0];
        req_ky        = vec[k + 9][1:0];
        req_kz        = vec[k + 10][1:0];
        req_shear_x   = vec[k + 11];
        req_shear_y   = vec[k + 12];
        req_record    = {vec[k + 24], vec[k + 23], vec[k + 22], vec[k + 21], vec[k + 20], vec[k + 19],
                         vec[k + 18], vec[k + 17], vec[k + 16], vec[k + 15], vec[k + 14], vec[k + 13]};
        req_tag       = sent[7:0];
      end
      #1;
      if (rsp_valid && rsp_ready) begin
        k = got * Fields;
        if (rsp_tag !== got[7:0] || rsp_hit !== vec[k + 25][0] || rsp_t !== vec[k + 26]
            || rsp_u !== vec[k + 27] || rsp_v !== vec[k + 28]) begin
          $display("netlist FAIL: cycle %0d, IU test %0d: origin %h %h %h direction %h %h %h t_min %h t_best %h",
                   cycle, got, vec[k], vec[k + 1], vec[k + 2], vec[k + 3], vec[k + 4], vec[k + 5],
                   vec[k + 6], vec[k + 7]);
          $display("  expected tag %h hit %h t %h u %h v %h; actual tag %h hit %h t %h u %h v %h",
                   got[7:0], vec[k + 25][0], vec[k + 26], vec[k + 27], vec[k + 28],
                   rsp_tag, rsp_hit, rsp_t, rsp_u, rsp_v);
          $fatal(1);
        end
        got = got + 1;
        last = cycle;
      end
      if (req_valid && req_ready) sent = sent + 1;
      if (sent == got) last = cycle;
      if (cycle - last > Timeout) begin
        $display("netlist FAIL: no response for %0d cycles at cycle %0d (IU test %0d)", Timeout, cycle, got);
        $fatal(1);
      end
      clk = 1'b1;
      #1 clk = 1'b0;
    end
    $display("netlist ok: %0d IU tests match the model in %0d cycles", n, cycle);
    $finish;
  end

endmodule
