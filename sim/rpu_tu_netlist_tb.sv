// Testbench for a Yosys netlist of rpu_tu_cosim_top (rtl/flow.py synth --unit tu): reads
// the memory image, the tu_cfg, the rays with the Tracer's expected responses and its
// IU tests that tu_cosim --write-vectors wrote, each stream as its words. Up to Slots
// rays are in the unit at once (one at a time for one slot, as in tu_cosim), with random
// stalls on every port; a behavioural memory serves the image's lines in order after 1-4
// cycles (the memory streams are one field each: an address, a line). Each IU test is
// answered after 1-4 cycles with the recorded iu_rsp of its ray's next test in walk
// order, the tests of different slots in random order; the iu_req is compared with the
// recorded one in the bits it records as compared. With more than one slot the IU tag
// names the slot (rpu_tu_slots), so the testbench follows the unit's rule (a ray goes to
// the lowest free slot; a slot is free from its response's hand-over) and checks the tag
// against it instead of the ray's. With Pipe = 1 (rpu_tu_pipe) Slots is the rays the
// testbench keeps in the unit, a ray may have several tests in flight and the IU tag
// names an entry of the unit's test table: each request is matched to the ray whose next
// test has its ray fields and record (t_best is the unit's of the time, not compared),
// and answered with that test's recorded iu_rsp under the request's tag, the tests in
// flight answered in random order. Every response, matched to its ray by tag, is
// compared with the Tracer's in the bits the vectors mark (tu_cosim's expected_of). No
// field is named here (spec/streams.toml): flow.py passes the stream widths and the tag
// fields' low bits from the spec, and a mismatch prints the streams in hex, most
// significant word first, as docs/streams.md lays them out. Stops at the first mismatch.
//   Vrpu_tu_netlist_tb +vectors=FILE [+seed=N]
`timescale 1ns / 1ps
module rpu_tu_netlist_tb #(
  parameter integer CfgBits = 1,
  parameter integer ReqBits = 1,
  parameter integer RspBits = 1,
  parameter integer MemReqBits = 32,
  parameter integer MemRspBits = 128,
  parameter integer IuReqBits = 1,
  parameter integer IuRspBits = 1,
  parameter integer TagBits = 8,
  parameter integer RspTagLsb = 0,
  parameter integer IuReqTagLsb = 0,
  parameter integer IuRspTagLsb = 0,
  parameter integer IuReqTBestLsb = 0,
  parameter integer Slots = 1,
  parameter integer Pipe = 0
);

  localparam integer MaxWords = 1 << 20;
  localparam integer MaxRays = 1 << 16;
  localparam integer MaxTests = 1 << 18;
  localparam integer CfgWords = (CfgBits + 31) / 32;
  localparam integer ReqWords = (ReqBits + 31) / 32;
  localparam integer RspWords = (RspBits + 31) / 32;
  localparam integer IuReqWords = (IuReqBits + 31) / 32;
  localparam integer IuRspWords = (IuRspBits + 31) / 32;
  localparam integer LineWords = MemRspBits / 32;
  localparam integer RayFields = ReqWords + 1 + 2 * RspWords;       // request, IU tests, expected, compared bits
  localparam integer TestFields = 2 * IuReqWords + IuRspWords;      // expected request, compared bits, answer
  localparam integer StallPercent = 8;
  localparam integer Timeout = 100000;
  localparam integer MemSlots = 128;                                 // memory requests in flight at most
  localparam integer Pool = 256;                                     // IU tests in flight at most (Pipe)

  reg                   clk = 1'b0;
  reg                   rst_n = 1'b0;
  reg  [CfgBits-1:0]    cfg = '0;
  reg                   req_valid = 1'b0;
  wire                  req_ready;
  reg  [ReqBits-1:0]    req = '0;
  wire                  rsp_valid;
  reg                   rsp_ready = 1'b0;
  wire [RspBits-1:0]    rsp;
  wire                  mem_req_valid;
  reg                   mem_req_ready = 1'b0;
  wire [MemReqBits-1:0] mem_req;
  reg                   mem_rsp_valid = 1'b0;
  wire                  mem_rsp_ready;
  reg  [MemRspBits-1:0] mem_rsp = '0;
  wire                  iu_req_valid;
  reg                   iu_req_ready = 1'b0;
  wire [IuReqBits-1:0]  iu_req;
  reg                   iu_rsp_valid = 1'b0;
  wire                  iu_rsp_ready;
  reg  [IuRspBits-1:0]  iu_rsp = '0;

  rpu_tu_cosim_top dut (
    .clk_i(clk), .rst_ni(rst_n), .cfg_i(cfg),
    .req_valid_i(req_valid), .req_ready_o(req_ready), .req_i(req),
    .rsp_valid_o(rsp_valid), .rsp_ready_i(rsp_ready), .rsp_o(rsp),
    .mem_req_valid_o(mem_req_valid), .mem_req_ready_i(mem_req_ready), .mem_req_o(mem_req),
    .mem_rsp_valid_i(mem_rsp_valid), .mem_rsp_ready_o(mem_rsp_ready), .mem_rsp_i(mem_rsp),
    .iu_req_valid_o(iu_req_valid), .iu_req_ready_i(iu_req_ready), .iu_req_o(iu_req),
    .iu_rsp_valid_i(iu_rsp_valid), .iu_rsp_ready_o(iu_rsp_ready), .iu_rsp_i(iu_rsp)
  );

  reg [31:0] mem [0:MaxWords-1];
  reg [31:0] cfg_words [0:CfgWords-1];
  reg [31:0] ray [0:MaxRays*RayFields-1];
  reg [31:0] test [0:MaxTests*TestFields-1];

  // Stream values assembled from the words at `at` of `ray` or `test`, word 0 lowest.
  reg [ReqWords*32-1:0]   req_flat;
  reg [RspWords*32-1:0]   want_rsp, care_rsp;
  reg [IuReqWords*32-1:0] want_iu, care_iu;
  reg [IuRspWords*32-1:0] answer;
  reg [CfgWords*32-1:0]   cfg_flat;
  reg [MemRspBits-1:0]    line;

  // Memory requests in flight and when each may answer.
  reg [MemReqBits-1:0] mem_addr [0:MemSlots-1];
  integer    mem_due [0:MemSlots-1];
  integer    mem_head, mem_tail;
  // Per slot: its ray (while busy), that ray's next IU test and the end of its tests,
  // and its IU test in flight (each slot waits for its answer) with when it may answer.
  reg        busy [0:Slots-1];
  integer    slot_ray [0:Slots-1];
  integer    next_test [0:Slots-1];
  integer    tests_end [0:Slots-1];
  reg        iu_pending [0:Slots-1];
  integer    iu_due [0:Slots-1];
  // Pipe: the IU tests in flight, each with its tag, its test in the file and when it
  // may answer.
  reg [TagBits-1:0] pool_tag [0:Pool-1];
  integer    pool_test [0:Pool-1];
  integer    pool_due [0:Pool-1];
  integer    pool_n, pick, j;
  // Each ray's first IU test in the file.
  integer    first_test [0:MaxRays];

  reg [1023:0] path;
  integer fd, words, n, tests, i, k, w, s, sent, got, cycle, last, seed, ok, free, answering, r;
  reg [TagBits-1:0] tag;

  task automatic load_ray(input integer r);
    integer b, j;
    begin
      b = r * RayFields;
      for (j = 0; j < ReqWords; j = j + 1) req_flat[j*32 +: 32] = ray[b + j];
      for (j = 0; j < RspWords; j = j + 1) begin
        want_rsp[j*32 +: 32] = ray[b + ReqWords + 1 + j];
        care_rsp[j*32 +: 32] = ray[b + ReqWords + 1 + RspWords + j];
      end
    end
  endtask

  task automatic load_test(input integer t);
    integer b, j;
    begin
      b = t * TestFields;
      for (j = 0; j < IuReqWords; j = j + 1) begin
        want_iu[j*32 +: 32] = test[b + j];
        care_iu[j*32 +: 32] = test[b + IuReqWords + j];
      end
      for (j = 0; j < IuRspWords; j = j + 1) answer[j*32 +: 32] = test[b + 2 * IuReqWords + j];
    end
  endtask

  task automatic fail_ray(input integer r);
    begin
      load_ray(r);
      $display("  ray %0d: tu_req %h", r, req_flat[ReqBits-1:0]);
      $fatal(1);
    end
  endtask

  // A failure no one ray is known for: the rays in the unit, then stop.
  task automatic fail_in_flight;
    integer j;
    begin
      for (j = 0; j < Slots; j = j + 1) begin
        if (busy[j]) begin
          load_ray(slot_ray[j]);
          $display("  slot %0d: ray %0d: tu_req %h", j, slot_ray[j], req_flat[ReqBits-1:0]);
        end
      end
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
    for (i = 0; i < CfgWords; i = i + 1) ok = ok + $fscanf(fd, "%h", cfg_words[i]);
    for (i = 0; i < words; i = i + 1) ok = ok + $fscanf(fd, "%h", mem[i]);
    for (i = 0; i < n * RayFields; i = i + 1) ok = ok + $fscanf(fd, "%h", ray[i]);
    for (i = 0; i < tests * TestFields; i = i + 1) ok = ok + $fscanf(fd, "%h", test[i]);
    $fclose(fd);
    if (ok != CfgWords + words + n * RayFields + tests * TestFields) begin
      $display("netlist FAIL: %0s: %0d words unreadable", path,
               CfgWords + words + n * RayFields + tests * TestFields - ok);
      $fatal(2);
    end
    for (i = 0; i < CfgWords; i = i + 1) cfg_flat[i*32 +: 32] = cfg_words[i];
    cfg = cfg_flat[CfgBits-1:0];
    first_test[0] = 0;
    for (i = 0; i < n; i = i + 1) first_test[i + 1] = first_test[i] + ray[i * RayFields + ReqWords];
    if (first_test[n] != tests) begin
      $display("netlist FAIL: %0s: the rays count %0d IU tests, the file holds %0d", path, first_test[n], tests);
      $fatal(2);
    end
    for (s = 0; s < Slots; s = s + 1) begin
      busy[s] = 1'b0;
      iu_pending[s] = 1'b0;
    end

    reset_dut();
    pool_n = 0;

    sent = 0;
    got = 0;
    last = 0;
    mem_head = 0;
    mem_tail = 0;
    for (cycle = 0; got < n; cycle = cycle + 1) begin
      // The unit's rule: the next ray goes to the lowest free slot.
      free = -1;
      for (s = Slots - 1; s >= 0; s = s - 1) if (!busy[s]) free = s;
      // Inputs of this cycle: up to Slots rays in the unit, stalls everywhere.
      req_valid = free >= 0 && sent < n && ({$random(seed)} % 100) >= StallPercent;
      if (sent < n) begin
        load_ray(sent);
        req = req_flat[ReqBits-1:0];
      end
      rsp_ready     = ({$random(seed)} % 100) >= StallPercent;
      mem_req_ready = ({$random(seed)} % 100) >= StallPercent;
      mem_rsp_valid = mem_head != mem_tail && mem_due[mem_head % MemSlots] <= cycle
                      && ({$random(seed)} % 100) >= StallPercent;
      if (mem_rsp_valid) begin
        // mem_req is {tag, addr}; the answer {tag, data} (answered in order: a walker
        // ignores the tag, a pipelined unit's line table finds its entry by it).
        k = mem_addr[mem_head % MemSlots][31:0] / 4;
        line[MemRspBits-1:32*LineWords] = mem_addr[mem_head % MemSlots][MemReqBits-1:32];
        // Whole-value writes of the DUT's inputs: Verilator 5.006 did not pass a
        // part-select write of mem_rsp to the port.
        for (w = 0; w < LineWords; w = w + 1) line[w*32 +: 32] = mem[k + w];
        mem_rsp = line;
      end
      // One due answer, from a random slot (Pipe: test in flight) onwards.
      answering = -1;
      pick = -1;
      if (Pipe != 0) begin
        k = pool_n > 0 ? {$random(seed)} % pool_n : 0;
        for (i = 0; i < pool_n; i = i + 1) begin
          j = (k + i) % pool_n;
          if (pick < 0 && pool_due[j] <= cycle) pick = j;
        end
      end else begin
        k = {$random(seed)} % Slots;
        for (i = 0; i < Slots; i = i + 1) begin
          s = (k + i) % Slots;
          if (answering < 0 && iu_pending[s] && iu_due[s] <= cycle) answering = s;
        end
      end
      iu_req_ready = ({$random(seed)} % 100) >= StallPercent;
      iu_rsp_valid = (answering >= 0 || pick >= 0) && ({$random(seed)} % 100) >= StallPercent;
      if (iu_rsp_valid) begin
        if (Pipe != 0) begin
          load_test(pool_test[pick]);
          answer[IuRspTagLsb +: TagBits] = pool_tag[pick];
        end else begin
          load_test(next_test[answering] - 1);
          if (Slots > 1) answer[IuRspTagLsb +: TagBits] = TagBits'(answering);
        end
        iu_rsp = answer[IuRspBits-1:0];
      end
      #1;

      if (rsp_valid && rsp_ready) begin
        tag = rsp[RspTagLsb +: TagBits];
        k = -1;
        for (s = 0; s < Slots; s = s + 1) if (busy[s] && TagBits'(slot_ray[s]) == tag) k = s;
        if (k < 0) begin
          $display("netlist FAIL: cycle %0d: a response (tag %h) for no ray in the unit", cycle, tag);
          $fatal(1);
        end
        r = slot_ray[k];
        load_ray(r);
        if (((rsp ^ want_rsp[RspBits-1:0]) & care_rsp[RspBits-1:0]) !== '0 || next_test[k] != tests_end[k]) begin
          $display("netlist FAIL: cycle %0d, ray %0d: expected tu_rsp %h in the bits %h", cycle, r,
                   want_rsp[RspBits-1:0], care_rsp[RspBits-1:0]);
          $display("  actual %h; IU tests taken %0d of %0d", rsp, next_test[k] - first_test[r],
                   tests_end[k] - first_test[r]);
          fail_ray(r);
        end
        busy[k] = 1'b0;
        got = got + 1;
        last = cycle;
      end
      if (mem_req_valid && mem_req_ready) begin
        if (mem_req[31:0] % (4 * LineWords) != 0 || mem_req[31:0] / 4 + LineWords > words
            || mem_tail - mem_head == MemSlots) begin
          $display("netlist FAIL: cycle %0d: memory request at %h: unaligned, outside the %0d-word image, or %0d in flight",
                   cycle, mem_req[31:0], words, MemSlots + 1);
          fail_in_flight();
        end
        mem_addr[mem_tail % MemSlots] = mem_req;
        mem_due[mem_tail % MemSlots] = cycle + 1 + {$random(seed)} % 4;
        mem_tail = mem_tail + 1;
      end
      if (mem_rsp_valid && mem_rsp_ready) mem_head = mem_head + 1;
      if (iu_req_valid && iu_req_ready && Pipe != 0) begin
        // Whose test: the ray whose next test has these ray fields and this record.
        s = -1;
        for (j = 0; j < Slots; j = j + 1) begin
          if (s < 0 && busy[j] && next_test[j] < tests_end[j]) begin
            load_test(next_test[j]);
            care_iu[IuReqTagLsb +: TagBits] = '0;
            care_iu[IuReqTBestLsb +: 32] = '0;
            if (((iu_req ^ want_iu[IuReqBits-1:0]) & care_iu[IuReqBits-1:0]) === '0) s = j;
          end
        end
        if (s < 0 || pool_n == Pool) begin
          $display("netlist FAIL: cycle %0d: IU request with tag %h is no ray's next test (or %0d in flight): iu_req %h",
                   cycle, iu_req[IuReqTagLsb +: TagBits], Pool + 1, iu_req);
          fail_in_flight();
        end
        pool_tag[pool_n] = iu_req[IuReqTagLsb +: TagBits];
        pool_test[pool_n] = next_test[s];
        pool_due[pool_n] = cycle + 1 + {$random(seed)} % 4;
        pool_n = pool_n + 1;
        next_test[s] = next_test[s] + 1;
      end else if (iu_req_valid && iu_req_ready) begin
        // Whose test: the slot the tag names, or the one slot.
        s = Slots > 1 ? integer'(iu_req[IuReqTagLsb +: TagBits]) : 0;
        if (s >= Slots || !busy[s] || iu_pending[s]) begin
          $display("netlist FAIL: cycle %0d: IU request with tag %h: no slot of that index holds a ray waiting for none",
                   cycle, iu_req[IuReqTagLsb +: TagBits]);
          $display("  iu_req %h", iu_req);
          $fatal(1);
        end
        r = slot_ray[s];
        load_test(next_test[s]);
        if (Slots > 1) care_iu[IuReqTagLsb +: TagBits] = '0;
        if (next_test[s] >= tests_end[s]
            || ((iu_req ^ want_iu[IuReqBits-1:0]) & care_iu[IuReqBits-1:0]) !== '0) begin
          $display("netlist FAIL: cycle %0d: IU request %0d of the walk (of %0d) differs: iu_req %h", cycle,
                   next_test[s] - first_test[r], tests_end[s] - first_test[r], iu_req);
          $display("  expected %h in the bits %h", want_iu[IuReqBits-1:0], care_iu[IuReqBits-1:0]);
          fail_ray(r);
        end
        next_test[s] = next_test[s] + 1;
        iu_pending[s] = 1'b1;
        iu_due[s] = cycle + 1 + {$random(seed)} % 4;
      end
      if (iu_rsp_valid && iu_rsp_ready) begin
        if (Pipe != 0) begin
          pool_n = pool_n - 1;
          pool_tag[pick] = pool_tag[pool_n];
          pool_test[pick] = pool_test[pool_n];
          pool_due[pick] = pool_due[pool_n];
        end else begin
          iu_pending[answering] = 1'b0;
        end
      end
      if (req_valid && req_ready) begin
        busy[free] = 1'b1;
        slot_ray[free] = sent;
        next_test[free] = first_test[sent];
        tests_end[free] = first_test[sent + 1];
        sent = sent + 1;
        last = cycle;
      end
      if (cycle - last > Timeout) begin
        $display("netlist FAIL: no response for %0d cycles at cycle %0d; the rays in the unit:", Timeout, cycle);
        fail_in_flight();
      end
      clk = 1'b1;
      #1 clk = 1'b0;
    end
    $display("netlist ok: %0d rays (%0d IU tests) match the Tracer in %0d cycles", n, tests, cycle);
    $finish;
  end

endmodule
