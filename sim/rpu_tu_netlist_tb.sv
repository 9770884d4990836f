// Testbench for a Yosys netlist of rpu_tu_cosim_top (rtl/flow.py synth --unit tu): reads
// the memory image, configuration, rays and the Tracer's results and IU tests that
// tu_cosim --write-vectors wrote. The rays go in one at a time (as in tu_cosim) with
// random stalls on every port; a behavioural memory serves the image's 16-byte lines
// in order after 1-4 cycles; the IU port is answered with the Tracer's IU tests in walk
// order after 1-4 cycles (a miss carries random t, u, v), each request checked against
// the recorded test (tag, t_best, record). Every response is compared with the Tracer:
// tag, hit, the counters, and t, u, v, prim on a hit. Stops at the first mismatch.
//   Vrpu_tu_netlist_tb +vectors=FILE [+seed=N]
`timescale 1ns / 1ps
module rpu_tu_netlist_tb;

  localparam integer MaxWords = 1 << 20;
  localparam integer MaxRays = 1 << 16;
  localparam integer MaxTests = 1 << 18;
  localparam integer RayFields = 18;   // 10 input words (the last: its IU tests), 8 expected
  localparam integer TestFields = 17;  // t_best, 12 record words, hit, t, u, v
  localparam integer StallPercent = 8;
  localparam integer Timeout = 100000;

  reg          clk = 1'b0;
  reg          rst_n = 1'b0;
  reg  [31:0]  cfg_kd_nodes = '0, cfg_prim_refs = '0, cfg_isect_records = '0;
  reg  [95:0]  cfg_bounds_lo = '0, cfg_bounds_hi = '0;
  reg  [7:0]   cfg_kd_scale_exponent = '0;
  reg          req_valid = 1'b0;
  wire         req_ready;
  reg  [7:0]   req_tag = '0;
  reg  [95:0]  req_origin = '0, req_direction = '0;
  reg  [31:0]  req_t_min = '0, req_t_max = '0;
  reg          req_any_hit = 1'b0;
  wire         rsp_valid;
  reg          rsp_ready = 1'b0;
  wire [7:0]   rsp_tag;
  wire         rsp_hit, rsp_fault;
  wire [31:0]  rsp_t, rsp_u, rsp_v, rsp_prim, rsp_nodes, rsp_leaves, rsp_tests;
  wire         mem_req_valid;
  reg          mem_req_ready = 1'b0;
  wire [31:0]  mem_req_addr;
  reg          mem_rsp_valid = 1'b0;
  wire         mem_rsp_ready;
  reg  [127:0] mem_rsp_data = '0;
  wire         iu_req_valid;
  reg          iu_req_ready = 1'b0;
  wire [7:0]   iu_req_tag;
  wire [95:0]  iu_req_origin, iu_req_direction;
  wire [63:0]  iu_req_shear;
  wire [31:0]  iu_req_t_min, iu_req_t_best;
  wire [5:0]   iu_req_axes;
  wire [383:0] iu_req_record;
  reg          iu_rsp_valid = 1'b0;
  wire         iu_rsp_ready;
  reg  [7:0]   iu_rsp_tag = '0;
  reg          iu_rsp_hit = 1'b0;
  reg  [31:0]  iu_rsp_t = '0, iu_rsp_u = '0, iu_rsp_v = '0;

  rpu_tu_cosim_top dut (
    .clk_i(clk), .rst_ni(rst_n),
    .cfg_kd_nodes_i(cfg_kd_nodes), .cfg_prim_refs_i(cfg_prim_refs), .cfg_isect_records_i(cfg_isect_records),
    .cfg_bounds_lo_i(cfg_bounds_lo), .cfg_bounds_hi_i(cfg_bounds_hi),
    .cfg_kd_scale_exponent_i(cfg_kd_scale_exponent),
    .req_valid_i(req_valid), .req_ready_o(req_ready), .req_tag_i(req_tag), .req_origin_i(req_origin),
    .req_direction_i(req_direction), .req_t_min_i(req_t_min), .req_t_max_i(req_t_max),
    .req_any_hit_i(req_any_hit),
    .rsp_valid_o(rsp_valid), .rsp_ready_i(rsp_ready), .rsp_tag_o(rsp_tag), .rsp_hit_o(rsp_hit),
    .rsp_t_o(rsp_t), .rsp_u_o(rsp_u), .rsp_v_o(rsp_v), .rsp_prim_o(rsp_prim), .rsp_nodes_o(rsp_nodes),
    .rsp_leaves_o(rsp_leaves), .rsp_tests_o(rsp_tests), .rsp_fault_o(rsp_fault),
    .mem_req_valid_o(mem_req_valid), .mem_req_ready_i(mem_req_ready), .mem_req_addr_o(mem_req_addr),
    .mem_rsp_valid_i(mem_rsp_valid), .mem_rsp_ready_o(mem_rsp_ready), .mem_rsp_data_i(mem_rsp_data),
    .iu_req_valid_o(iu_req_valid), .iu_req_ready_i(iu_req_ready), .iu_req_tag_o(iu_req_tag),
    .iu_req_origin_o(iu_req_origin), .iu_req_direction_o(iu_req_direction), .iu_req_t_min_o(iu_req_t_min),
    .iu_req_t_best_o(iu_req_t_best), .iu_req_axes_o(iu_req_axes), .iu_req_shear_o(iu_req_shear),
    .iu_req_record_o(iu_req_record),
    .iu_rsp_valid_i(iu_rsp_valid), .iu_rsp_ready_o(iu_rsp_ready), .iu_rsp_tag_i(iu_rsp_tag),
    .iu_rsp_hit_i(iu_rsp_hit), .iu_rsp_t_i(iu_rsp_t), .iu_rsp_u_i(iu_rsp_u), .iu_rsp_v_i(iu_rsp_v)
  );

  reg [31:0] mem [0:MaxWords-1];
  reg [31:0] cfg [0:9];
  reg [31:0] ray [0:MaxRays*RayFields-1];
  reg [31:0] test [0:MaxTests*TestFields-1];

  // Memory requests in flight (at most 3: a record's lines) and when each may answer.
  reg [31:0] mem_addr [0:7];
  integer    mem_due [0:7];
  integer    mem_head, mem_tail;
  // The IU test in flight (one at a time) and when it may answer.
  integer    iu_pending, iu_due;

  reg [1023:0] path;
  integer fd, words, n, tests, i, k, sent, got, cycle, last, seed, ok, next_test, ray_tests_end;

  task automatic fail_ray(input integer r);
    integer b;
    begin
      b = r * RayFields;
      $display("  ray %0d: origin %h %h %h direction %h %h %h t_min %h t_max %h any_hit %0d", r, ray[b],
               ray[b + 1], ray[b + 2], ray[b + 3], ray[b + 4], ray[b + 5], ray[b + 6], ray[b + 7], ray[b + 8]);
      $fatal(1);
    end
  endtask

  `include "rpu_netlist_vectors.svh"

  initial begin
    open_vectors(path, fd, seed);
    ok = $fscanf(fd, "%d %d %d\n", words, n, tests);
    if (ok != 3 || words > MaxWords || n > MaxRays || tests > MaxTests) begin
      $display("netlist FAIL: bad header in %0s (or more than %0d words, %0d rays, %0d IU tests)", path, MaxWords,
               MaxRays, MaxTests);
      $fatal(2);
    end
    ok = 0;
    for (i = 0; i < 10; i = i + 1) ok = ok + $fscanf(fd, "%h", cfg[i]);
    for (i = 0; i < words; i = i + 1) ok = ok + $fscanf(fd, "%h", mem[i]);
    for (i = 0; i < n * RayFields; i = i + 1) ok = ok + $fscanf(fd, "%h", ray[i]);
    for (i = 0; i < tests * TestFields; i = i + 1) ok = ok + $fscanf(fd, "%h", test[i]);
    $fclose(fd);
    if (ok != 10 + words + n * RayFields + tests * TestFields) begin
      $display("netlist FAIL: %0s: %0d words unreadable", path, 10 + words + n * RayFields + tests * TestFields - ok);
      $fatal(2);
    end
    cfg_kd_nodes      = cfg[0];
    cfg_prim_refs     = cfg[1];
    cfg_isect_records = cfg[2];
    cfg_bounds_lo     = {cfg[5], cfg[4], cfg[3]};
    cfg_bounds_hi     = {cfg[8], cfg[7], cfg[6]};
    cfg_kd_scale_exponent = cfg[9][7:0];

    reset_dut();

    sent = 0;
    got = 0;
    last = 0;
    mem_head = 0;
    mem_tail = 0;
    iu_pending = 0;
    iu_due = 0;
    next_test = 0;
    ray_tests_end = 0;
    for (cycle = 0; got < n; cycle = cycle + 1) begin
      // Inputs of this cycle: one ray at a time, stalls everywhere.
      req_valid = sent == got && sent < n && ({$random(seed)} % 100) >= StallPercent;
      if (sent < n) begin
        k = sent * RayFields;
        req_tag       = sent[7:0];
        req_origin    = {ray[k + 2], ray[k + 1], ray[k]};
        req_direction = {ray[k + 5], ray[k + 4], ray[k + 3]};
        req_t_min     = ray[k + 6];
        req_t_max     = ray[k + 7];
        req_any_hit   = ray[k + 8][0];
      end
      rsp_ready     = ({$random(seed)} % 100) >= StallPercent;
      mem_req_ready = ({$random(seed)} % 100) >= StallPercent;
      mem_rsp_valid = mem_head != mem_tail && mem_due[mem_head % 8] <= cycle
                      && ({$random(seed)} % 100) >= StallPercent;
      if (mem_rsp_valid) begin
        k = mem_addr[mem_head % 8] / 4;
        mem_rsp_data = {mem[k + 3], mem[k + 2], mem[k + 1], mem[k]};
      end
      iu_req_ready = !iu_pending && ({$random(seed)} % 100) >= StallPercent;
      iu_rsp_valid = iu_pending && iu_due <= cycle && ({$random(seed)} % 100) >= StallPercent;
      if (iu_rsp_valid) begin
        k = (next_test - 1) * TestFields;
        iu_rsp_tag = got[7:0];
        iu_rsp_hit = test[k + 13][0];
        iu_rsp_t   = iu_rsp_hit ? test[k + 14] : $random(seed);
        iu_rsp_u   = iu_rsp_hit ? test[k + 15] : $random(seed);
        iu_rsp_v   = iu_rsp_hit ? test[k + 16] : $random(seed);
      end
      #1;

      if (rsp_valid && sent == got) begin
        $display("netlist FAIL: cycle %0d: a response without a ray", cycle);
        $fatal(1);
      end
      if (rsp_valid && rsp_ready) begin
        k = got * RayFields;
        if (rsp_tag !== got[7:0] || rsp_fault !== 1'b0 || rsp_hit !== ray[k + 10][0]
            || rsp_nodes !== ray[k + 15] || rsp_leaves !== ray[k + 16] || rsp_tests !== ray[k + 17]
            || (ray[k + 10][0] && (rsp_t !== ray[k + 11] || rsp_u !== ray[k + 12] || rsp_v !== ray[k + 13]
                                   || rsp_prim !== ray[k + 14]))
            || next_test != ray_tests_end) begin
          $display("netlist FAIL: cycle %0d, ray %0d: expected tag %h hit %h t %h u %h v %h prim %0d nodes %0d leaves %0d tests %0d",
                   cycle, got, got[7:0], ray[k + 10][0], ray[k + 11], ray[k + 12], ray[k + 13], ray[k + 14],
                   ray[k + 15], ray[k + 16], ray[k + 17]);
          $display("  actual tag %h hit %h t %h u %h v %h prim %0d nodes %0d leaves %0d tests %0d fault %h; IU tests taken %0d of %0d",
                   rsp_tag, rsp_hit, rsp_t, rsp_u, rsp_v, rsp_prim, rsp_nodes, rsp_leaves, rsp_tests, rsp_fault,
                   next_test - (ray_tests_end - ray[k + 9]), ray[k + 9]);
          fail_ray(got);
        end
        got = got + 1;
        last = cycle;
      end
      if (mem_req_valid && mem_req_ready) begin
        if (mem_req_addr[3:0] != 4'd0 || mem_req_addr / 4 + 4 > words || mem_tail - mem_head == 8) begin
          $display("netlist FAIL: cycle %0d: memory request at %h: unaligned, outside the %0d-word image, or 9 in flight",
                   cycle, mem_req_addr, words);
          fail_ray(got);
        end
        mem_addr[mem_tail % 8] = mem_req_addr;
        mem_due[mem_tail % 8] = cycle + 1 + {$random(seed)} % 4;
        mem_tail = mem_tail + 1;
      end
      if (mem_rsp_valid && mem_rsp_ready) mem_head = mem_head + 1;
      if (iu_req_valid && iu_req_ready) begin
        k = next_test * TestFields;
        if (next_test >= ray_tests_end || iu_req_tag !== got[7:0] || iu_req_t_best !== test[k]
            || iu_req_record !== {test[k + 12], test[k + 11], test[k + 10], test[k + 9], test[k + 8], test[k + 7],
                                  test[k + 6], test[k + 5], test[k + 4], test[k + 3], test[k + 2], test[k + 1]}) begin
          $display("netlist FAIL: cycle %0d: IU request %0d of the walk (of %0d) differs: tag %h t_best %h (expected %h) record %h",
                   cycle, next_test - (ray_tests_end - ray[got * RayFields + 9]), ray[got * RayFields + 9],
                   iu_req_tag, iu_req_t_best, test[k], iu_req_record);
          fail_ray(got);
        end
        next_test = next_test + 1;
        iu_pending = 1;
        iu_due = cycle + 1 + {$random(seed)} % 4;
      end
      if (iu_rsp_valid && iu_rsp_ready) iu_pending = 0;
      if (req_valid && req_ready) begin
        ray_tests_end = ray_tests_end + ray[sent * RayFields + 9];
        sent = sent + 1;
        last = cycle;
      end
      if (cycle - last > Timeout) begin
        $display("netlist FAIL: no response for %0d cycles at cycle %0d", Timeout, cycle);
        fail_ray(got);
      end
      clk = 1'b1;
      #1 clk = 1'b0;
    end
    $display("netlist ok: %0d rays (%0d IU tests) match the Tracer in %0d cycles", n, tests, cycle);
    $finish;
  end

endmodule
