// A shader core (SPU; docs/chip.md "Shader core"): Threads hardware threads in chunks
// of ChunkSize that step in lockstep by the functional model's rule (the smallest live
// pc of a chunk issues, the lanes standing there execute it; docs/shader-core.md).
//
// Per chunk: a state machine picks the next pc, fetches the instruction from the code
// memory and waits until its registers are free (an in-order scoreboard: a count per
// register of the lane writes under way). One chunk instruction is issued at a time,
// round robin among the ready chunks, and its lanes enter the pipeline one a cycle:
//   S0  the lane (or a value returned by the memory, the special-function unit or the
//       ray units, which has priority) reads the register file;
//   E   operands in hand: the checks of spec/isa.toml [[fault]] in their order, the
//       thread's pc, stacks and counters, and hand-offs to the load/store unit, the
//       special-function unit and the ray units; everything else enters the datapath;
//   W   rpu_spu_datapath.Latency cycles later: the register file is written.
// The register file is twelve rpu_ram (three read copies x four lanes), one word per
// thread and register; a register reads as zero until its first write, which writes
// all four lanes. The trace ports report each chunk step (issue), each executed
// instruction (retire), each register write (writeback) and each fault, for the
// lockstep checker (sim/spu_checker.hpp).
module rpu_spu #(
  parameter int unsigned CoreId     = 0,
  parameter int unsigned Cores      = 1,     // on the chip: pixel p runs on thread p mod (Cores x Threads)
  parameter int unsigned Threads    = 4,
  parameter int unsigned ChunkSize  = 2,
  parameter int unsigned Registers  = 32,
  parameter int unsigned CallDepth  = 16,
  parameter int unsigned StackBytes = 16384,
  parameter int unsigned SfuUnits   = 1,
  parameter int unsigned CodeWords  = 4096,
  parameter int unsigned ExpBits    = rpu_pkg::FormatFp32ExponentBits,
  parameter int unsigned FracBits   = rpu_pkg::FormatFp32FractionBits,
  localparam int unsigned CodeAddrBits = $clog2(CodeWords)
) (
  input  logic                      clk_i,
  input  logic                      rst_ni,

  // The firmware's code, written before a launch.
  input  logic                      code_we_i,
  input  logic [CodeAddrBits-1:0]   code_addr_i,
  input  logic [63:0]               code_data_i,

  // A frame: start_i for one cycle with launch_i, which stays until done_o.
  input  logic                      start_i,
  input  rpu_pkg::launch_t          launch_i,
  // A fault at pixel stop_pixel_i somewhere on the chip: no round past it starts.
  input  logic                      stop_i,
  input  logic [31:0]               stop_pixel_i,
  output logic                      done_o,
  // The core's time, counted in the cycles count_i is high (the chip's frame).
  input  logic                      count_i,
  output rpu_pkg::core_counters_t   counters_o,

  output logic                      cache_req_valid_o,
  input  logic                      cache_req_ready_i,
  output rpu_pkg::cache_req_t       cache_req_o,
  input  logic                      cache_rsp_valid_i,
  output logic                      cache_rsp_ready_o,
  input  rpu_pkg::cache_rsp_t       cache_rsp_i,

  output logic                      trace_req_valid_o,
  input  logic                      trace_req_ready_i,
  output rpu_pkg::trace_req_t       trace_req_o,
  input  logic                      trace_rsp_valid_i,
  output logic                      trace_rsp_ready_o,
  input  rpu_pkg::trace_rsp_t       trace_rsp_i,

  // Trace ports: taken every cycle they are valid.
  output logic                      issue_valid_o,
  output rpu_pkg::issue_t           issue_o,
  output logic                      retire_valid_o,
  output rpu_pkg::retire_t          retire_o,
  output logic                      wb_valid_o,
  output rpu_pkg::writeback_t       wb_o,
  output logic                      fault_valid_o,
  output rpu_pkg::fault_t           fault_o
);

  localparam int unsigned Chunks       = Threads / ChunkSize;
  localparam int unsigned TB           = Threads > 1 ? $clog2(Threads) : 1;
  localparam int unsigned CB           = Chunks > 1 ? $clog2(Chunks) : 1;
  localparam int unsigned LB           = ChunkSize > 1 ? $clog2(ChunkSize) : 1;
  localparam int unsigned RegBits      = rpu_pkg::IsaDstWidth;
  localparam int unsigned RfAddrBits   = $clog2(Threads * Registers);
  localparam int unsigned RsAddrBits   = $clog2(Threads * CallDepth);
  localparam int unsigned RspBits      = $clog2(CallDepth + 1);
  localparam int unsigned StackSlots   = StackBytes / 16;
  localparam int unsigned SspBits      = $clog2(StackSlots + 1);
  localparam int unsigned CntBits      = $clog2(ChunkSize + 1);
  localparam int unsigned FlightBits   = 16;
  localparam int unsigned TotalThreads = Cores * Threads;
  localparam int unsigned Thread0      = CoreId * Threads;  // this core's first global thread
  // A queue to a unit and the room a chunk instruction needs in it (rpu_pkg's
  // UnitQueueChunks and UnitQueueSlack; the cycle model's rule is the same).
  localparam int unsigned QueueDepth   = rpu_pkg::UnitQueueChunks * ChunkSize + rpu_pkg::UnitQueueSlack;
  localparam int unsigned QueueNeed    = ChunkSize + rpu_pkg::UnitQueueSlack;
  localparam int unsigned QCountBits   = $clog2(QueueDepth + 1);
  // What comes back with a load, an sfu result and a ray.
  localparam int unsigned LsuTagBits   = TB + RegBits + 4 + 3;  // thread, dst, wmask, {broadcast, round, calli}
  localparam int unsigned SfuTagBits   = TB + RegBits + 4;

  // The chunk states.
  localparam logic [2:0] CIdle = 3'd0, CStart = 3'd1, CPick = 3'd2, CFetch = 3'd3, CFetchWait = 3'd4,
                         CReady = 3'd5, CBusy = 3'd6, CDrain = 3'd7;

  // ---------------------------------------------------------------------------------
  // Instruction fields.
  // ---------------------------------------------------------------------------------
  // The opcode as bits (rpu_pkg::opcode_e's values): Yosys 0.23 reads no enum casts.
  function automatic logic [rpu_pkg::IsaOpcodeWidth-1:0] f_op(input logic [63:0] w);
    f_op = w[rpu_pkg::IsaOpcodeLsb +: rpu_pkg::IsaOpcodeWidth];
  endfunction
  function automatic logic [RegBits-1:0] f_dst(input logic [63:0] w);
    f_dst = w[rpu_pkg::IsaDstLsb +: RegBits];
  endfunction
  function automatic logic [3:0] f_wmask(input logic [63:0] w);
    f_wmask = w[rpu_pkg::IsaWmaskLsb +: 4];
  endfunction
  function automatic logic [RegBits-1:0] f_a(input logic [63:0] w);
    f_a = w[rpu_pkg::IsaARegLsb +: RegBits];
  endfunction
  function automatic logic [RegBits-1:0] f_b(input logic [63:0] w);
    f_b = w[rpu_pkg::IsaBRegLsb +: RegBits];
  endfunction
  function automatic logic [RegBits-1:0] f_c(input logic [63:0] w);
    f_c = w[rpu_pkg::IsaCRegLsb +: RegBits];
  endfunction
  // The register read through copy 2: a store's data (dst field), else source c.
  function automatic logic [RegBits-1:0] f_third(input logic [63:0] w);
    f_third = rpu_pkg::isa_reads_dst(f_op(w)) ? f_dst(w) : f_c(w);
  endfunction
  function automatic logic [127:0] swizzle(input logic [127:0] v, input logic [7:0] s);
    for (int i = 0; i < 4; i++) swizzle[32*i +: 32] = v[32*s[2*i +: 2] +: 32];
  endfunction
  // A lane write of register r is under way (counts: one chunk's scoreboard).
  function automatic logic pending(input logic [$clog2(ChunkSize+1)*Registers-1:0] counts,
                                   input logic [RegBits-1:0] r);
    pending = 32'(r) < Registers && counts[$clog2(ChunkSize+1)*32'(r) +: $clog2(ChunkSize+1)] != '0;
  endfunction

  // ---------------------------------------------------------------------------------
  // State.
  // ---------------------------------------------------------------------------------
  // Per thread.
  logic [32*Threads-1:0]        pc_d, pc_q;
  logic [Threads-1:0]           live_d, live_q;
  logic [RspBits*Threads-1:0]   rsp_d, rsp_q;       // return addresses held
  logic [SspBits*Threads-1:0]   ssp_d, ssp_q;       // memory-stack slots used
  logic [32*Threads-1:0]        retired_d, retired_q;
  logic [Registers*Threads-1:0] written_d, written_q;
  // Per chunk.
  logic [3*Chunks-1:0]          state_d, state_q;
  logic [32*Chunks-1:0]         base_d, base_q;     // round x TotalThreads: lane l's pixel is base + Thread0 + chunk x ChunkSize + l
  logic [32*Chunks-1:0]         ib_pc_d, ib_pc_q;
  logic [64*Chunks-1:0]         ib_insn_d, ib_insn_q;
  logic [Chunks-1:0]            ib_pcfault_d, ib_pcfault_q;
  logic [Chunks-1:0]            ended_d, ended_q;   // the issued instruction's lanes are past E
  logic [CntBits*Chunks-1:0]    calli_d, calli_q;   // calli lanes waiting for their table entry
  logic [FlightBits*Chunks-1:0] flight_d, flight_q; // lanes issued and not finished
  logic [CntBits*Registers*Chunks-1:0] sb_d, sb_q;  // lane writes under way per register
  // The issue.
  logic [CB-1:0]                rr_d, rr_q;         // the chunk that issued last
  logic                         seq_valid_d, seq_valid_q;
  logic [CB-1:0]                seq_chunk_d, seq_chunk_q;
  logic [31:0]                  seq_pc_d, seq_pc_q;
  logic [63:0]                  seq_insn_d, seq_insn_q;
  logic                         seq_pcfault_d, seq_pcfault_q;
  logic [ChunkSize-1:0]         seq_lanes_d, seq_lanes_q;
  logic [QCountBits-1:0]        trace_count_d, trace_count_q;

  // The op from S0 in E.
  typedef struct packed {
    logic                valid;
    logic                ret;       // a value handed back, not an instruction
    logic [TB-1:0]       thread;
    logic [31:0]         pc;
    logic [63:0]         insn;
    logic                pcfault;   // the pc is past the code (insn is 0)
    logic                last;      // the last lane of its chunk instruction
    logic                counted;   // it counts in the scoreboard of its destination
    // A returned value: where it goes and how.
    logic [RegBits-1:0]  r_dst;
    logic [3:0]          r_wmask;
    logic [127:0]        r_value;
    logic                r_round;   // round into the format (a float load), then widen
    logic                r_widen;   // a format value (sfu): widen
    logic                r_setpc;   // calli's table entry: the new pc
    logic                r_tfault;  // the traversal faulted
  } op_t;
  op_t s0, e_d, e_q;

  // ---------------------------------------------------------------------------------
  // Memories: code, register file, return stacks.
  // ---------------------------------------------------------------------------------
  logic [CodeAddrBits-1:0] code_raddr;
  logic [63:0]             code_rdata;
  rpu_ram #(.Width(64), .Depth(CodeWords)) u_code (
    .clk_i, .we_i(code_we_i), .waddr_i(code_addr_i), .wdata_i(code_data_i),
    .raddr_i(code_raddr), .rdata_o(code_rdata)
  );

  function automatic logic [RfAddrBits-1:0] rf_addr(input logic [TB-1:0] t, input logic [RegBits-1:0] r);
    rf_addr = RfAddrBits'(32'(t) * Registers + 32'(r));
  endfunction

  logic                  rf_we;
  logic [3:0]            rf_lane_we;
  logic [RfAddrBits-1:0] rf_waddr;
  logic [127:0]          rf_wdata;
  logic [3*RfAddrBits-1:0] rf_raddr;
  logic [3*128-1:0]      rf_rdata;
  for (genvar s = 0; s < 3; s++) begin : g_rf_copy
    for (genvar l = 0; l < 4; l++) begin : g_rf_lane
      rpu_ram #(.Width(32), .Depth(Threads * Registers)) u_rf (
        .clk_i, .we_i(rf_we && rf_lane_we[l]), .waddr_i(rf_waddr), .wdata_i(rf_wdata[32*l +: 32]),
        .raddr_i(rf_raddr[RfAddrBits*s +: RfAddrBits]), .rdata_o(rf_rdata[128*s + 32*l +: 32])
      );
    end
  end

  logic                  rs_we;
  logic [RsAddrBits-1:0] rs_waddr, rs_raddr;
  logic [31:0]           rs_wdata, rs_rdata;
  rpu_ram #(.Width(32), .Depth(Threads * CallDepth)) u_return_stack (
    .clk_i, .we_i(rs_we), .waddr_i(rs_waddr), .wdata_i(rs_wdata), .raddr_i(rs_raddr), .rdata_o(rs_rdata)
  );

  // ---------------------------------------------------------------------------------
  // Per-chunk views.
  // ---------------------------------------------------------------------------------
  logic [Chunks-1:0]     any_live;
  logic [32*Chunks-1:0]  min_pc;
  logic [Chunks-1:0]     sb_ok, res_ok, ready;
  logic [ChunkSize*Chunks-1:0] at_pc;  // live lanes standing at the fetched pc

  // The free entries of the queues.
  logic [QCountBits-1:0] lsu_free, sfu_free;
  logic [QCountBits-1:0] trace_free;
  assign trace_free = QCountBits'(QueueDepth) - trace_count_q;

  for (genvar c = 0; c < Chunks; c++) begin : g_chunk_view
    // The smallest live pc.
    always_comb begin : min_live_pc
      any_live[c]          = 1'b0;
      min_pc[32*c +: 32]   = '1;
      for (int l = 0; l < ChunkSize; l++) begin
        if (live_q[c*ChunkSize + l]) begin
          any_live[c] = 1'b1;
          if (pc_q[32*(c*ChunkSize + l) +: 32] < min_pc[32*c +: 32]) min_pc[32*c +: 32] = pc_q[32*(c*ChunkSize + l) +: 32];
        end
      end
    end
    for (genvar l = 0; l < ChunkSize; l++) begin : g_at
      assign at_pc[c*ChunkSize + l] = live_q[c*ChunkSize + l] && pc_q[32*(c*ChunkSize + l) +: 32] == ib_pc_q[32*c +: 32];
    end

    // The fetched instruction's registers are free.
    logic [63:0]            w;
    logic [rpu_pkg::IsaOpcodeWidth-1:0] op;
    logic                   pend_a, pend_b, pend_c, pend_d;
    assign w  = ib_insn_q[64*c +: 64];
    assign op = f_op(w);
    assign pend_a = rpu_pkg::isa_reads_a(op) && pending(sb_q[CntBits*Registers*c +: CntBits*Registers], f_a(w));
    assign pend_b = rpu_pkg::isa_reads_b(op) && pending(sb_q[CntBits*Registers*c +: CntBits*Registers], f_b(w));
    assign pend_c = rpu_pkg::isa_reads_c(op) && pending(sb_q[CntBits*Registers*c +: CntBits*Registers], f_c(w));
    assign pend_d = (rpu_pkg::isa_writes_dst(op) || rpu_pkg::isa_reads_dst(op))
                    && pending(sb_q[CntBits*Registers*c +: CntBits*Registers], f_dst(w));
    assign sb_ok[c] = ib_pcfault_q[c] || !(pend_a || pend_b || pend_c || pend_d);

    // Room for every lane in the queue the instruction hands its lanes to.
    always_comb begin : queue_room
      res_ok[c] = 1'b1;
      if (!ib_pcfault_q[c]) begin
        if (32'(rpu_pkg::isa_class(op)) == rpu_pkg::IsaClassMem || op == rpu_pkg::OpCalli) begin
          res_ok[c] = 32'(lsu_free) >= QueueNeed;
        end else if (32'(rpu_pkg::isa_class(op)) == rpu_pkg::IsaClassTrace) begin
          res_ok[c] = 32'(trace_free) >= QueueNeed;
        end else if (32'(rpu_pkg::isa_class(op)) == rpu_pkg::IsaClassSfu) begin
          res_ok[c] = 32'(sfu_free) >= QueueNeed;
        end
      end
    end
    assign ready[c] = state_q[3*c +: 3] == CReady && sb_ok[c] && res_ok[c];
  end

  // ---------------------------------------------------------------------------------
  // Fetch: one chunk a cycle reads the code memory.
  // ---------------------------------------------------------------------------------
  logic [Chunks-1:0] fetch_grant;
  always_comb begin : pick_fetch_chunk
    fetch_grant = '0;
    code_raddr  = '0;
    for (int c = Chunks - 1; c >= 0; c--) begin
      if (state_q[3*c +: 3] == CFetch) begin
        fetch_grant    = '0;
        fetch_grant[c] = 1'b1;
        code_raddr     = ib_pc_q[32*c +: CodeAddrBits];
      end
    end
  end

  // ---------------------------------------------------------------------------------
  // Returns: a value back from the load/store unit, the sfu or the ray units takes S0.
  // ---------------------------------------------------------------------------------
  logic                  lsu_out_valid, lsu_out_ready, sfu_out_valid, sfu_out_ready;
  logic [LsuTagBits-1:0] lsu_out_tag;
  logic [127:0]          lsu_out_data;
  logic [SfuTagBits-1:0] sfu_out_tag;
  logic [127:0]          sfu_out_value;
  op_t                   ret_op;
  logic                  ret_valid;
  // A ray's answer has the first claim on S0, so the core takes one every cycle (and its
  // ready depends on nothing: no combinational path back into the ray units).
  assign trace_rsp_ready_o = 1'b1;
  logic                  ret_broadcast;  // ld1: the word in every lane
  logic [rpu_pkg::ThreadBits-TB-1:0] unused_tag_thread;

  always_comb begin : pick_return
    ret_op            = '0;
    ret_op.valid      = 1'b1;
    ret_op.ret        = 1'b1;
    lsu_out_ready     = 1'b0;
    sfu_out_ready     = 1'b0;
    ret_valid         = 1'b1;
    ret_broadcast     = 1'b0;
    unused_tag_thread = trace_rsp_i.tag[RegBits + 4 + TB +: rpu_pkg::ThreadBits - TB];
    if (trace_rsp_valid_i) begin
      {ret_op.thread, ret_op.r_dst, ret_op.r_wmask} =
          trace_rsp_i.tag[TB + RegBits + 4 - 1:0];
      ret_op.pc       = trace_rsp_i.pc;
      ret_op.r_tfault = trace_rsp_i.fault;
      // A miss is (+inf, 0, 0, 0xffffffff) (spec/isa.toml trace).
      ret_op.r_value  = trace_rsp_i.hit ? {trace_rsp_i.prim, trace_rsp_i.v, trace_rsp_i.u, trace_rsp_i.t}
                                        : {32'hffff_ffff, 32'd0, 32'd0, 32'h7f80_0000};
    end else if (lsu_out_valid) begin
      lsu_out_ready = 1'b1;
      {ret_op.thread, ret_op.r_dst, ret_op.r_wmask, ret_broadcast, ret_op.r_round, ret_op.r_setpc} = lsu_out_tag;
      ret_op.r_value = ret_broadcast ? {4{lsu_out_data[31:0]}} : lsu_out_data;
    end else if (sfu_out_valid) begin
      sfu_out_ready = 1'b1;
      {ret_op.thread, ret_op.r_dst, ret_op.r_wmask} = sfu_out_tag;
      ret_op.r_widen = 1'b1;
      ret_op.r_value = sfu_out_value;
    end else begin
      ret_valid = 1'b0;
    end
    // Every return but calli's answers a counted register write.
    ret_op.counted = !ret_op.r_setpc;
  end

  // ---------------------------------------------------------------------------------
  // Issue: the sequencer holds one chunk instruction and hands its lanes to S0.
  // ---------------------------------------------------------------------------------
  // A fault in E stops the lanes after it in its chunk (later pixels).
  logic                  kill;
  logic [CB-1:0]         kill_chunk;
  logic [LB-1:0]         kill_lane;
  logic [ChunkSize-1:0]  kill_after;  // the lanes after kill_lane
  logic [ChunkSize-1:0]  seq_live, seq_kill, remaining, emit_bit, remaining_after;
  logic                  emit, seq_free;
  logic [LB-1:0]         emit_lane;
  logic                  selected;
  logic [CB-1:0]         sel;
  logic                  end_now;       // the sequencer's chunk instruction ends without a last lane
  logic [CB-1:0]         end_now_chunk;

  always_comb begin : next_lane
    for (int l = 0; l < ChunkSize; l++) begin
      kill_after[l] = kill && LB'(l) > kill_lane;
      seq_live[l]   = live_q[32'(seq_chunk_q) * ChunkSize + l];
      seq_kill[l]   = kill_after[l] && kill_chunk == seq_chunk_q;
    end
    remaining = seq_valid_q ? seq_lanes_q & seq_live & ~seq_kill : '0;
    emit      = remaining != '0 && !ret_valid;
    emit_lane = '0;
    for (int l = ChunkSize - 1; l >= 0; l--) begin
      if (remaining[l]) emit_lane = LB'(l);
    end
    emit_bit        = emit ? ChunkSize'(1) << emit_lane : '0;
    remaining_after = remaining & ~emit_bit;
    seq_free        = remaining_after == '0;
    end_now         = seq_valid_q && remaining == '0;
    end_now_chunk   = seq_chunk_q;
  end

  // Round robin among the ready chunks, after the one that issued last.
  always_comb begin : pick_ready_chunk
    selected = 1'b0;
    sel      = '0;
    for (int k = Chunks; k >= 1; k--) begin
      if (ready[(32'(rr_q) + k) % Chunks]) begin
        selected = 1'b1;
        sel      = CB'((32'(rr_q) + k) % Chunks);
      end
    end
    selected = selected && seq_free;
  end

  always_comb begin : next_sequencer
    seq_valid_d   = seq_valid_q && !seq_free;
    seq_chunk_d   = seq_chunk_q;
    seq_pc_d      = seq_pc_q;
    seq_insn_d    = seq_insn_q;
    seq_pcfault_d = seq_pcfault_q;
    seq_lanes_d   = remaining_after;
    rr_d          = rr_q;
    if (selected) begin
      seq_valid_d   = 1'b1;
      seq_chunk_d   = sel;
      seq_pc_d      = ib_pc_q[32*sel +: 32];
      seq_insn_d    = ib_insn_q[64*sel +: 64];
      seq_pcfault_d = ib_pcfault_q[sel];
      seq_lanes_d   = at_pc[ChunkSize*sel +: ChunkSize];
      rr_d          = sel;
    end
  end

  assign issue_valid_o = selected;
  always_comb begin : issue_record
    issue_o       = '0;
    issue_o.core  = rpu_pkg::CoreBits'(CoreId);
    issue_o.chunk = rpu_pkg::ThreadBits'(sel);
    issue_o.pc    = ib_pc_q[32*sel +: 32];
    issue_o.lanes = rpu_pkg::ChunkLanes'(at_pc[ChunkSize*sel +: ChunkSize]);
  end

  // S0: the return, or the sequencer's next lane.
  always_comb begin : pick_s0
    s0 = '0;
    if (ret_valid) begin
      s0 = ret_op;
    end else if (emit) begin
      s0.valid   = 1'b1;
      s0.thread  = TB'(32'(seq_chunk_q) * ChunkSize + 32'(emit_lane));
      s0.pc      = seq_pc_q;
      s0.insn    = seq_insn_q;
      s0.pcfault = seq_pcfault_q;
      s0.last    = remaining_after == '0;
      s0.counted = !seq_pcfault_q && rpu_pkg::isa_writes_dst(f_op(seq_insn_q))
                   && 32'(f_dst(seq_insn_q)) < Registers;
    end
  end
  assign e_d = s0;

  // Register file and return stack reads.
  always_comb begin : read_addrs
    rf_raddr = {rf_addr(s0.thread, f_third(s0.insn)), rf_addr(s0.thread, f_b(s0.insn)),
                rf_addr(s0.thread, f_a(s0.insn))};
    rs_raddr = RsAddrBits'(32'(s0.thread) * CallDepth + 32'(rsp_q[RspBits*s0.thread +: RspBits]) - 1);
  end

  // ---------------------------------------------------------------------------------
  // E: the op with its operands.
  // ---------------------------------------------------------------------------------
  logic [63:0]          w;
  logic [rpu_pkg::IsaOpcodeWidth-1:0] op;
  logic [CB-1:0]        e_chunk;
  logic [LB-1:0]        e_lane;
  logic [31:0]          e_pixel, e_gid;
  logic [RegBits-1:0]   dst;
  logic [3:0]           wmask;
  logic                 fmt_i, mods;
  logic [31:0]          imm;
  logic [127:0]         a_reg, b_reg, c_reg, src_a, src_b, src_c;  // registers as read; swizzled sources
  logic [2:0]           neg, abs;
  logic [RspBits-1:0]   e_rsp;
  logic [SspBits-1:0]   e_ssp;
  logic [31:0]          e_retired;

  assign w         = e_q.insn;
  assign op        = f_op(w);
  assign e_chunk   = CB'(32'(e_q.thread) / ChunkSize);
  assign e_lane    = LB'(32'(e_q.thread) % ChunkSize);
  assign e_gid     = 32'(Thread0) + 32'(e_q.thread);
  assign e_pixel   = base_q[32*e_chunk +: 32] + e_gid;
  assign dst       = e_q.ret ? e_q.r_dst : f_dst(w);
  assign wmask     = e_q.ret ? e_q.r_wmask : f_wmask(w);
  assign fmt_i     = rpu_pkg::isa_format_i(op);
  assign mods      = !fmt_i;  // R format: neg on a, b, c and abs on a, b (used_bits keeps the rest 0)
  assign imm       = w[rpu_pkg::IsaImmLsb +: 32];
  assign e_rsp     = rsp_q[RspBits*e_q.thread +: RspBits];
  assign e_ssp     = ssp_q[SspBits*e_q.thread +: SspBits];
  assign e_retired = retired_q[32*e_q.thread +: 32];

  // A register reads as zero until its first write.
  function automatic logic [127:0] masked(input logic [127:0] v, input logic [Registers*Threads-1:0] wr,
                                          input logic [TB-1:0] t, input logic [RegBits-1:0] r);
    masked = 32'(r) < Registers && wr[Registers*32'(t) + 32'(r)] ? v : '0;
  endfunction
  assign a_reg = masked(rf_rdata[0 +: 128], written_q, e_q.thread, f_a(w));
  assign b_reg = masked(rf_rdata[128 +: 128], written_q, e_q.thread, f_b(w));
  assign c_reg = masked(rf_rdata[256 +: 128], written_q, e_q.thread, f_third(w));
  assign src_a = swizzle(a_reg, w[rpu_pkg::IsaASwizzleLsb +: 8]);
  assign src_b = swizzle(b_reg, w[rpu_pkg::IsaBSwizzleLsb +: 8]);
  assign src_c = swizzle(c_reg, w[rpu_pkg::IsaCSwizzleLsb +: 8]);
  assign neg = mods ? {w[rpu_pkg::IsaCNegLsb], w[rpu_pkg::IsaBNegLsb], w[rpu_pkg::IsaANegLsb]} : 3'b000;
  assign abs = mods ? {1'b0, w[rpu_pkg::IsaBAbsLsb], w[rpu_pkg::IsaAAbsLsb]} : 3'b000;

  // Addresses and their checks: word k of an access at addr + 4k.
  logic [31:0] shader_entry, mem_addr, stack_addr_push, stack_addr_pop, stack_top;
  logic        wide, store;
  logic [3:0]  mem_ok;
  assign shader_entry = launch_i.shader_table + {src_a[29:0], 2'b00};
  assign mem_addr     = op == rpu_pkg::OpCalli ? shader_entry : src_a[31:0] + imm;
  assign wide         = op == rpu_pkg::OpLd || op == rpu_pkg::OpLdf || op == rpu_pkg::OpSt;
  assign store        = op == rpu_pkg::OpSt || op == rpu_pkg::OpSt1;
  // The thread's stack: slot k (1-based) at the top minus 16k.
  assign stack_top       = rpu_pkg::DeviceStackBase + (e_gid + 32'd1) * StackBytes;
  assign stack_addr_push = stack_top - ((32'(e_ssp) + 32'd1) << 4);
  assign stack_addr_pop  = stack_top - (32'(e_ssp) << 4);

  for (genvar k = 0; k < 4; k++) begin : g_memcheck
    rpu_spu_memcheck u_check (
      .addr_i(mem_addr + 32'(4 * k)), .bytes_i(k == 0 && wide && !store ? 5'd16 : 5'd4), .write_i(store),
      .pixel_i(e_pixel), .launch_i, .ok_o(mem_ok[k])
    );
  end

  // The checks of spec/isa.toml [[fault]], in their order.
  logic                              f_any;
  logic [rpu_pkg::FaultKindBits-1:0] f_kind;
  logic [31:0]                       f_addr;
  logic                              illegal, bad_reg;
  logic [63:0]                       used;
  assign used = rpu_pkg::isa_used_bits(op);
  always_comb begin : find_fault
    illegal = used == '0 || (w & ~used) != '0;
    bad_reg = ((rpu_pkg::isa_writes_dst(op) || rpu_pkg::isa_reads_dst(op)) && 32'(f_dst(w)) >= Registers)
              || (rpu_pkg::isa_reads_a(op) && 32'(f_a(w)) >= Registers)
              || (rpu_pkg::isa_reads_b(op) && 32'(f_b(w)) >= Registers)
              || (rpu_pkg::isa_reads_c(op) && 32'(f_c(w)) >= Registers);
    f_any  = 1'b1;
    f_addr = '0;
    f_kind = '0;
    if (e_q.ret) begin
      f_any  = e_q.r_tfault;
      f_kind = rpu_pkg::FaultKindBits'(rpu_pkg::FaultTraversal);
    end else if (e_q.pcfault) begin
      f_kind = rpu_pkg::FaultKindBits'(rpu_pkg::FaultPc);
    end else if (illegal) begin
      f_kind = rpu_pkg::FaultKindBits'(rpu_pkg::FaultIllegal);
    end else if (e_retired >= launch_i.watchdog) begin
      f_kind = rpu_pkg::FaultKindBits'(rpu_pkg::FaultWatchdog);
    end else if (bad_reg) begin
      f_kind = rpu_pkg::FaultKindBits'(rpu_pkg::FaultRegister);
    end else begin
      unique case (op)
        rpu_pkg::OpLd, rpu_pkg::OpLdf, rpu_pkg::OpLd1, rpu_pkg::OpLd1f: begin
          f_any  = !mem_ok[0];
          f_kind = rpu_pkg::FaultKindBits'(rpu_pkg::FaultMemory);
          f_addr = mem_addr;
        end
        rpu_pkg::OpSt: begin
          // The first word of the write mask that may not be stored.
          f_any  = 1'b0;
          f_kind = rpu_pkg::FaultKindBits'(rpu_pkg::FaultMemory);
          for (int k = 3; k >= 0; k--) begin
            if (wmask[k] && !mem_ok[k]) begin
              f_any  = 1'b1;
              f_addr = mem_addr + 32'(4 * k);
            end
          end
        end
        rpu_pkg::OpSt1: begin
          f_any  = wmask != 4'b0001 || !mem_ok[0];
          f_kind = rpu_pkg::FaultKindBits'(wmask != 4'b0001 ? rpu_pkg::FaultIllegal : rpu_pkg::FaultMemory);
          f_addr = wmask != 4'b0001 ? '0 : mem_addr;
        end
        rpu_pkg::OpPush: begin
          f_any  = 32'(e_ssp) == StackSlots;
          f_kind = rpu_pkg::FaultKindBits'(rpu_pkg::FaultStackOverflow);
        end
        rpu_pkg::OpPop: begin
          f_any  = e_ssp == '0;
          f_kind = rpu_pkg::FaultKindBits'(rpu_pkg::FaultStackUnderflow);
        end
        rpu_pkg::OpCall, rpu_pkg::OpMtra: begin
          f_any  = 32'(e_rsp) == CallDepth;
          f_kind = rpu_pkg::FaultKindBits'(rpu_pkg::FaultCallOverflow);
        end
        rpu_pkg::OpCalli: begin
          if (src_a[31:0] >= launch_i.shader_count) begin
            f_kind = rpu_pkg::FaultKindBits'(rpu_pkg::FaultShaderId);
            f_addr = src_a[31:0];
          end else if (!mem_ok[0]) begin
            f_kind = rpu_pkg::FaultKindBits'(rpu_pkg::FaultMemory);
            f_addr = mem_addr;
          end else begin
            f_any  = 32'(e_rsp) == CallDepth;
            f_kind = rpu_pkg::FaultKindBits'(rpu_pkg::FaultCallOverflow);
          end
        end
        rpu_pkg::OpRet, rpu_pkg::OpMfra: begin
          f_any  = e_rsp == '0;
          f_kind = rpu_pkg::FaultKindBits'(rpu_pkg::FaultCallUnderflow);
        end
        rpu_pkg::OpRdsr: begin
          f_any  = !(imm == rpu_pkg::SpecialPixel || imm == rpu_pkg::SpecialLaunch
                     || imm == rpu_pkg::SpecialThread || imm == rpu_pkg::SpecialParams);
          f_kind = rpu_pkg::FaultKindBits'(rpu_pkg::FaultIllegal);
        end
        default: f_any = 1'b0;
      endcase
    end
  end

  logic e_inst, e_fault, e_exec;  // an instruction; it faults; it executes
  assign e_inst  = e_q.valid && !e_q.ret;
  assign e_fault = e_q.valid && f_any;
  assign e_exec  = e_inst && !f_any;

  assign kill       = e_fault;
  assign kill_chunk = e_chunk;
  assign kill_lane  = e_lane;

  // rdsr pixel: (x, y) of the pixel index by multiplication (launch_t div_magic).
  logic [63:0] div_product;
  logic [31:0] div_t1, div_q, pix_x;
  assign div_product = {32'd0, launch_i.div_magic} * {32'd0, e_pixel};
  assign div_t1      = div_product[63:32];
  logic unused_div;
  assign unused_div = ^div_product[31:0];
  assign div_q       = (div_t1 + ((e_pixel - div_t1) >> launch_i.div_shift1)) >> launch_i.div_shift2;
  assign pix_x       = e_pixel - div_q * launch_i.width;

  logic [127:0] special;
  always_comb begin : special_value
    unique case (imm[1:0])
      2'(rpu_pkg::SpecialPixel):  special = {32'd0, e_pixel, div_q, pix_x};
      2'(rpu_pkg::SpecialLaunch): special = {launch_i.max_depth, launch_i.spp, launch_i.height, launch_i.width};
      2'(rpu_pkg::SpecialThread): special = {32'(e_lane), 32'(e_chunk), 32'(CoreId), e_gid};
      default:                    special = {64'd0, launch_i.launch_bytes, rpu_pkg::DeviceLaunchBase};
    endcase
    if (op == rpu_pkg::OpMfra) special = {4{rs_rdata}};
  end

  // Where the op goes.
  logic to_lsu, to_sfu, to_trace, to_dp, async;
  logic [3:0] store_words;
  assign store_words = op == rpu_pkg::OpSt ? wmask : op == rpu_pkg::OpPush ? 4'b1111 : 4'b0001;
  always_comb begin : route_op
    to_lsu   = 1'b0;
    to_sfu   = 1'b0;
    to_trace = 1'b0;
    if (e_exec) begin
      unique case (op)
        rpu_pkg::OpLd, rpu_pkg::OpLdf, rpu_pkg::OpLd1, rpu_pkg::OpLd1f, rpu_pkg::OpPop, rpu_pkg::OpCalli,
        rpu_pkg::OpSt1, rpu_pkg::OpPush: to_lsu = 1'b1;
        rpu_pkg::OpSt:                   to_lsu = wmask != '0;
        rpu_pkg::OpRcp, rpu_pkg::OpRsq, rpu_pkg::OpSqrt: to_sfu = 1'b1;
        rpu_pkg::OpTrace, rpu_pkg::OpTracea: to_trace = 1'b1;
        default: ;
      endcase
    end
  end
  // A load, sfu op or ray finishes when its value comes back; a store when it is sent.
  assign async = to_sfu || to_trace || (to_lsu && !store && op != rpu_pkg::OpPush);
  assign to_dp = e_q.valid;

  // Load/store unit.
  logic lsu_in_ready, lsu_idle;
  rpu_spu_lsu #(.TagBits(LsuTagBits), .Depth(QueueDepth)) u_lsu (
    .clk_i, .rst_ni,
    .in_valid_i(to_lsu), .in_ready_o(lsu_in_ready),
    .in_store_i(store || op == rpu_pkg::OpPush),
    .in_tag_i({e_q.thread, dst, wmask, op == rpu_pkg::OpLd1 || op == rpu_pkg::OpLd1f,
               op == rpu_pkg::OpLdf || op == rpu_pkg::OpLd1f, op == rpu_pkg::OpCalli}),
    .in_addr_i(op == rpu_pkg::OpPush ? stack_addr_push : op == rpu_pkg::OpPop ? stack_addr_pop : mem_addr),
    .in_wide_i(wide || op == rpu_pkg::OpPush || op == rpu_pkg::OpPop),
    .in_words_i(store_words),
    .in_data_i(op == rpu_pkg::OpPush ? src_a : c_reg),
    .free_o(lsu_free),
    .cache_req_valid_o, .cache_req_ready_i, .cache_req_o,
    .cache_rsp_valid_i, .cache_rsp_ready_o, .cache_rsp_i,
    .out_valid_o(lsu_out_valid), .out_ready_i(lsu_out_ready), .out_tag_o(lsu_out_tag), .out_data_o(lsu_out_data),
    .idle_o(lsu_idle)
  );

  // Special-function unit: rcp, rsq, sqrt on the sources in the format.
  logic         sfu_in_ready;
  logic [127:0] sfu_a;
  rpu_spu_sfu #(
    .ExpBits(ExpBits), .FracBits(FracBits), .Units(SfuUnits), .Depth(QueueDepth), .TagBits(SfuTagBits)
  ) u_sfu (
    .clk_i, .rst_ni,
    .in_valid_i(to_sfu), .in_ready_o(sfu_in_ready), .in_tag_i({e_q.thread, dst, wmask}),
    .in_op_i(op == rpu_pkg::OpRcp ? rpu_pkg::FpOpRcp : op == rpu_pkg::OpRsq ? rpu_pkg::FpOpRsqrt : rpu_pkg::FpOpSqrt),
    .in_wmask_i(wmask), .in_a_i(sfu_a),
    .out_valid_o(sfu_out_valid), .out_ready_i(sfu_out_ready), .out_tag_o(sfu_out_tag), .out_value_o(sfu_out_value),
    .free_o(sfu_free)
  );

  // Rays: a queue to the ray units.
  logic                            trace_in_ready;
  rpu_pkg::trace_req_t             trace_in;
  always_comb begin : trace_request
    trace_in           = '0;
    trace_in.tag       = rpu_pkg::TraceTagBits'({rpu_pkg::CoreBits'(CoreId), rpu_pkg::ThreadBits'(e_q.thread), dst, wmask});
    trace_in.pc        = e_q.pc;
    trace_in.origin    = src_a[95:0];
    trace_in.t_min     = src_a[127:96];
    trace_in.direction = src_b[95:0];
    trace_in.t_max     = src_b[127:96];
    trace_in.any_hit   = op == rpu_pkg::OpTracea;
  end
  rpu_fifo #(.Width(rpu_pkg::TraceReqBits), .Depth(QueueDepth)) u_trace_queue (
    .clk_i, .rst_ni,
    .in_valid_i(to_trace), .in_ready_o(trace_in_ready), .in_data_i(trace_in),
    .out_valid_o(trace_req_valid_o), .out_ready_i(trace_req_ready_i), .out_data_o(trace_req_o)
  );
  always_comb begin : count_queued_rays
    trace_count_d = trace_count_q;
    if (to_trace && !(trace_req_valid_o && trace_req_ready_i)) trace_count_d = trace_count_q + QCountBits'(1);
    else if (!to_trace && trace_req_valid_o && trace_req_ready_i) trace_count_d = trace_count_q - QCountBits'(1);
  end

  // The datapath: every op, so that results and the bookkeeping of finished ops come
  // out in order at W.
  localparam int unsigned CtrlBits = 3 + TB + RegBits + 4;
  logic                wb_valid;
  logic [127:0]        wb_result;
  logic [CtrlBits-1:0] wb_ctrl;
  logic                w_write, w_sb_dec, w_fin;
  logic [TB-1:0]       w_thread;
  logic [RegBits-1:0]  w_dst;
  logic [3:0]          w_wmask;
  logic                e_write;
  assign e_write = e_q.ret ? !e_q.r_tfault && !e_q.r_setpc
                           : e_exec && !async && rpu_pkg::isa_writes_dst(op);

  rpu_spu_datapath #(.ExpBits(ExpBits), .FracBits(FracBits), .CtrlBits(CtrlBits)) u_datapath (
    .clk_i, .rst_ni,
    .valid_i(to_dp), .op_i(op), .hand_i(e_q.ret), .hand_round_i(e_q.r_round), .hand_widen_i(e_q.r_widen),
    .a_i(e_q.ret ? e_q.r_value : src_a), .b_i(src_b), .c_i(src_c), .neg_i(e_q.ret ? 3'b000 : neg),
    .abs_i(e_q.ret ? 3'b000 : abs), .imm_i(imm), .raw_i(special),
    .ctrl_i({e_write, e_q.counted && !(e_exec && async), e_q.ret || !(e_exec && async), e_q.thread, dst, wmask}),
    .valid_o(wb_valid), .result_o(wb_result), .ctrl_o(wb_ctrl), .src_a_fmt_o(sfu_a)
  );
  assign {w_write, w_sb_dec, w_fin, w_thread, w_dst, w_wmask} = wb_valid ? wb_ctrl : '0;

  // ---------------------------------------------------------------------------------
  // W: the register file.
  // ---------------------------------------------------------------------------------
  logic w_first;  // the register's first write: the other lanes become 0
  assign w_first    = !written_q[Registers*32'(w_thread) + 32'(w_dst)];
  assign rf_we      = w_write;
  assign rf_waddr   = rf_addr(w_thread, w_dst);
  assign rf_lane_we = w_first ? 4'b1111 : w_wmask;
  always_comb begin : mask_write_data
    for (int l = 0; l < 4; l++) rf_wdata[32*l +: 32] = w_wmask[l] ? wb_result[32*l +: 32] : '0;
  end

  assign wb_valid_o = w_write;
  always_comb begin : writeback_record
    wb_o        = '0;
    wb_o.core   = rpu_pkg::CoreBits'(CoreId);
    wb_o.thread = rpu_pkg::ThreadBits'(w_thread);
    wb_o.dst    = w_dst;
    wb_o.wmask  = w_wmask;
    wb_o.value  = rf_wdata;
  end

  // ---------------------------------------------------------------------------------
  // E's effects on the thread; the retire and fault records.
  // ---------------------------------------------------------------------------------
  logic [31:0] pc_next;
  logic        pc_we, rsp_push, rsp_pop, ssp_push, ssp_pop, halt;
  always_comb begin : thread_effects
    pc_next  = e_q.pc + 32'd1;
    pc_we    = e_exec && op != rpu_pkg::OpCalli;
    rsp_push = 1'b0;
    rsp_pop  = 1'b0;
    ssp_push = e_exec && op == rpu_pkg::OpPush;
    ssp_pop  = e_exec && op == rpu_pkg::OpPop;
    halt     = e_exec && op == rpu_pkg::OpHalt;
    rs_we    = 1'b0;
    rs_wdata = e_q.pc + 32'd1;
    if (e_exec) begin
      unique case (op)
        rpu_pkg::OpBra: pc_next = imm;
        rpu_pkg::OpBz:  if (src_a[31:0] == '0) pc_next = imm;
        rpu_pkg::OpBnz: if (src_a[31:0] != '0) pc_next = imm;
        rpu_pkg::OpCall: begin
          pc_next  = imm;
          rsp_push = 1'b1;
          rs_we    = 1'b1;
        end
        rpu_pkg::OpCalli: begin
          rsp_push = 1'b1;
          rs_we    = 1'b1;
        end
        rpu_pkg::OpMtra: begin
          rsp_push = 1'b1;
          rs_we    = 1'b1;
          rs_wdata = src_a[31:0];
        end
        rpu_pkg::OpRet: begin
          pc_next = rs_rdata;
          rsp_pop = 1'b1;
        end
        rpu_pkg::OpMfra: rsp_pop = 1'b1;
        default: ;
      endcase
    end
    // calli's entry arrives: the call's target.
    if (e_q.valid && e_q.ret && e_q.r_setpc) begin
      pc_we   = 1'b1;
      pc_next = e_q.r_value[31:0];
    end
  end
  assign rs_waddr = RsAddrBits'(32'(e_q.thread) * CallDepth + 32'(e_rsp));

  assign retire_valid_o = e_exec;
  always_comb begin : retire_record
    retire_o        = '0;
    retire_o.core   = rpu_pkg::CoreBits'(CoreId);
    retire_o.thread = rpu_pkg::ThreadBits'(e_q.thread);
    retire_o.pc     = e_q.pc;
    retire_o.insn   = w;
    if (to_lsu || op == rpu_pkg::OpSt) begin
      retire_o.addr = op == rpu_pkg::OpPush ? stack_addr_push : op == rpu_pkg::OpPop ? stack_addr_pop : mem_addr;
    end
  end

  assign fault_valid_o = e_fault;
  always_comb begin : fault_record
    fault_o        = '0;
    fault_o.kind   = f_kind;
    fault_o.core   = rpu_pkg::CoreBits'(CoreId);
    fault_o.thread = rpu_pkg::ThreadBits'(e_q.thread);
    fault_o.pixel  = e_pixel;
    fault_o.pc     = e_q.pc;
    fault_o.addr   = f_addr;
  end

  // ---------------------------------------------------------------------------------
  // Per-thread state.
  // ---------------------------------------------------------------------------------
  logic [Chunks-1:0] init_chunk;  // the chunk starts a round: its threads start over

  for (genvar t = 0; t < Threads; t++) begin : g_thread
    localparam int unsigned C = t / ChunkSize;
    localparam int unsigned L = t % ChunkSize;
    logic                 here;
    logic [Registers-1:0] written_now;  // the register W writes this cycle
    assign here        = e_q.valid && 32'(e_q.thread) == t;
    assign written_now = w_write && 32'(w_thread) == t && 32'(w_dst) < Registers ? Registers'(1) << w_dst : '0;
    always_comb begin : next_thread
      pc_d[32*t +: 32]                  = pc_q[32*t +: 32];
      live_d[t]                         = live_q[t];
      rsp_d[RspBits*t +: RspBits]       = rsp_q[RspBits*t +: RspBits];
      ssp_d[SspBits*t +: SspBits]       = ssp_q[SspBits*t +: SspBits];
      retired_d[32*t +: 32]             = retired_q[32*t +: 32];
      written_d[Registers*t +: Registers] = written_q[Registers*t +: Registers];
      if (init_chunk[C]) begin
        pc_d[32*t +: 32]      = launch_i.raygen;
        live_d[t]             = base_q[32*C +: 32] + 32'(Thread0 + t) < launch_i.pixels;
        rsp_d[RspBits*t +: RspBits] = '0;
        ssp_d[SspBits*t +: SspBits] = '0;
        retired_d[32*t +: 32] = '0;
        written_d[Registers*t +: Registers] = '0;
      end else begin
        if (here && pc_we) pc_d[32*t +: 32] = pc_next;
        if (here && e_inst) retired_d[32*t +: 32] = retired_q[32*t +: 32] + 32'd1;
        if (here && rsp_push) rsp_d[RspBits*t +: RspBits] = rsp_q[RspBits*t +: RspBits] + RspBits'(1);
        if (here && rsp_pop) rsp_d[RspBits*t +: RspBits] = rsp_q[RspBits*t +: RspBits] - RspBits'(1);
        if (here && ssp_push) ssp_d[SspBits*t +: SspBits] = ssp_q[SspBits*t +: SspBits] + SspBits'(1);
        if (here && ssp_pop) ssp_d[SspBits*t +: SspBits] = ssp_q[SspBits*t +: SspBits] - SspBits'(1);
        if (here && (halt || e_fault)) live_d[t] = 1'b0;
        if (kill_after[L] && 32'(kill_chunk) == C) live_d[t] = 1'b0;
        written_d[Registers*t +: Registers] = written_q[Registers*t +: Registers] | written_now;
      end
    end
  end

  // ---------------------------------------------------------------------------------
  // Per-chunk state.
  // ---------------------------------------------------------------------------------
  logic [Chunks-1:0] chunk_end;
  always_comb begin : find_chunk_ends
    chunk_end = '0;
    if (e_inst && (e_q.last || e_fault)) chunk_end[e_chunk] = 1'b1;
    if (end_now) chunk_end[end_now_chunk] = 1'b1;
  end

  for (genvar c = 0; c < Chunks; c++) begin : g_chunk
    logic [31:0] first_pixel, next_base;
    logic        refuse;
    logic        s0_here, w_here, e_here;
    assign first_pixel = base_q[32*c +: 32] + 32'(Thread0 + c * ChunkSize);
    assign refuse      = first_pixel >= launch_i.pixels || (stop_i && first_pixel > stop_pixel_i);
    assign next_base   = base_q[32*c +: 32] + 32'(TotalThreads);
    assign s0_here     = s0.valid && !s0.ret && 32'(s0.thread) / ChunkSize == c;
    assign e_here      = e_q.valid && 32'(e_chunk) == c;
    assign w_here      = 32'(w_thread) / ChunkSize == c;
    assign init_chunk[c] = state_q[3*c +: 3] == CStart && !refuse;

    always_comb begin : next_chunk
      state_d[3*c +: 3]           = state_q[3*c +: 3];
      base_d[32*c +: 32]          = base_q[32*c +: 32];
      ib_pc_d[32*c +: 32]         = ib_pc_q[32*c +: 32];
      ib_insn_d[64*c +: 64]       = ib_insn_q[64*c +: 64];
      ib_pcfault_d[c]             = ib_pcfault_q[c];
      ended_d[c]                  = ended_q[c] || chunk_end[c];
      calli_d[CntBits*c +: CntBits] = calli_q[CntBits*c +: CntBits];
      flight_d[FlightBits*c +: FlightBits] = flight_q[FlightBits*c +: FlightBits]
          + FlightBits'(s0_here) - FlightBits'(w_fin && w_here);
      if (e_here && e_exec && op == rpu_pkg::OpCalli) calli_d[CntBits*c +: CntBits] = calli_q[CntBits*c +: CntBits] + CntBits'(1);
      if (e_here && e_q.ret && e_q.r_setpc) calli_d[CntBits*c +: CntBits] = calli_q[CntBits*c +: CntBits] - CntBits'(1);

      unique case (state_q[3*c +: 3])
        CIdle: if (start_i) begin
          state_d[3*c +: 3]  = CStart;
          base_d[32*c +: 32] = '0;
        end
        CStart: state_d[3*c +: 3] = refuse ? CIdle : CPick;
        CPick: begin
          if (!any_live[c]) begin
            state_d[3*c +: 3] = CDrain;
          end else begin
            ib_pc_d[32*c +: 32] = min_pc[32*c +: 32];
            if (min_pc[32*c +: 32] >= launch_i.code_words) begin
              ib_pcfault_d[c]       = 1'b1;
              ib_insn_d[64*c +: 64] = '0;
              state_d[3*c +: 3]     = CReady;
            end else begin
              ib_pcfault_d[c]   = 1'b0;
              state_d[3*c +: 3] = CFetch;
            end
          end
        end
        CFetch: if (fetch_grant[c]) state_d[3*c +: 3] = CFetchWait;
        CFetchWait: begin
          ib_insn_d[64*c +: 64] = code_rdata;
          state_d[3*c +: 3]     = CReady;
        end
        CReady: if (selected && sel == CB'(c)) begin
          state_d[3*c +: 3] = CBusy;
          ended_d[c]        = 1'b0;
        end
        CBusy: if (ended_d[c] && calli_d[CntBits*c +: CntBits] == '0) state_d[3*c +: 3] = CPick;
        CDrain: if (flight_q[FlightBits*c +: FlightBits] == '0) begin
          base_d[32*c +: 32] = next_base;
          state_d[3*c +: 3]  = CStart;
        end
        default: state_d[3*c +: 3] = CIdle;
      endcase
    end

    // Scoreboard: a lane write counts from S0 to W.
    for (genvar r = 0; r < Registers; r++) begin : g_sb
      logic inc, dec;
      assign inc = s0_here && s0.counted && 32'(f_dst(s0.insn)) == r;
      assign dec = w_sb_dec && w_here && 32'(w_dst) == r;
      assign sb_d[CntBits*(Registers*c + r) +: CntBits] = sb_q[CntBits*(Registers*c + r) +: CntBits]
          + CntBits'(inc) - CntBits'(dec);
    end
  end

  assign done_o = state_q == '0 && flight_q == '0 && lsu_idle && trace_count_q == '0;

  // ---------------------------------------------------------------------------------
  // Counters (docs/chip.md "Statistics"): why no instruction issues. A chunk with rays
  // out waits for rays, else one with loads out for memory, else it waits for the core
  // itself; the core waits for itself if any live chunk does, else for memory if any
  // does, else for rays (the core's own latencies are the shortest, rays the longest),
  // as the cycle model does.
  // ---------------------------------------------------------------------------------
  logic [FlightBits*Chunks-1:0] rays_d, rays_q, loads_d, loads_q;
  logic [Chunks-1:0]            chunk_dep, chunk_mem, chunk_ray;
  logic [TB-1:0]                ray_back_thread, load_back_thread;
  logic                         load_back;
  assign ray_back_thread  = trace_rsp_i.tag[RegBits + 4 +: TB];
  assign load_back_thread = lsu_out_tag[LsuTagBits - 1 -: TB];
  assign load_back        = lsu_out_valid && lsu_out_ready;
  for (genvar c = 0; c < Chunks; c++) begin : g_wait
    logic e_here, ray_out, ray_back, load_out, load_back_here, live;
    assign e_here         = e_q.valid && 32'(e_chunk) == c;
    assign ray_out        = e_here && to_trace;
    assign load_out       = e_here && to_lsu && async;
    assign ray_back       = trace_rsp_valid_i && 32'(ray_back_thread) / ChunkSize == c;
    assign load_back_here = load_back && 32'(load_back_thread) / ChunkSize == c;
    assign rays_d[FlightBits*c +: FlightBits] = rays_q[FlightBits*c +: FlightBits]
        + FlightBits'(ray_out) - FlightBits'(ray_back);
    assign loads_d[FlightBits*c +: FlightBits] = loads_q[FlightBits*c +: FlightBits]
        + FlightBits'(load_out) - FlightBits'(load_back_here);
    assign live         = state_q[3*c +: 3] != CIdle;
    assign chunk_ray[c] = live && rays_q[FlightBits*c +: FlightBits] != '0;
    assign chunk_mem[c] = live && !chunk_ray[c] && loads_q[FlightBits*c +: FlightBits] != '0;
    assign chunk_dep[c] = live && !chunk_ray[c] && !chunk_mem[c];
  end

  rpu_pkg::core_counters_t counters_d, counters_q;
  always_comb begin : count_waits
    counters_d = counters_q;
    if (count_i) begin
      if (selected) counters_d.chunk_issues = counters_q.chunk_issues + 32'd1;
      if (selected || emit)  counters_d.busy = counters_q.busy + 32'd1;
      else if (|chunk_dep)   counters_d.wait_dependency = counters_q.wait_dependency + 32'd1;
      else if (|chunk_mem)   counters_d.wait_memory = counters_q.wait_memory + 32'd1;
      else if (|chunk_ray)   counters_d.wait_trace = counters_q.wait_trace + 32'd1;
      else                   counters_d.idle = counters_q.idle + 32'd1;
    end
  end
  assign counters_o = counters_q;

  always_ff @(posedge clk_i or negedge rst_ni) begin : counter_regs
    if (!rst_ni) begin
      rays_q     <= '0;
      loads_q    <= '0;
      counters_q <= '0;
    end else begin
      rays_q     <= rays_d;
      loads_q    <= loads_d;
      counters_q <= counters_d;
    end
  end

  // ---------------------------------------------------------------------------------
  // Registers.
  // ---------------------------------------------------------------------------------
  always_ff @(posedge clk_i or negedge rst_ni) begin : regs
    if (!rst_ni) begin
      pc_q          <= '0;
      live_q        <= '0;
      rsp_q         <= '0;
      ssp_q         <= '0;
      retired_q     <= '0;
      written_q     <= '0;
      state_q       <= '0;
      base_q        <= '0;
      ib_pc_q       <= '0;
      ib_insn_q     <= '0;
      ib_pcfault_q  <= '0;
      ended_q       <= '0;
      calli_q       <= '0;
      flight_q      <= '0;
      sb_q          <= '0;
      rr_q          <= '0;
      seq_valid_q   <= 1'b0;
      seq_chunk_q   <= '0;
      seq_pc_q      <= '0;
      seq_insn_q    <= '0;
      seq_pcfault_q <= 1'b0;
      seq_lanes_q   <= '0;
      trace_count_q <= '0;
      e_q           <= '0;
    end else begin
      pc_q          <= pc_d;
      live_q        <= live_d;
      rsp_q         <= rsp_d;
      ssp_q         <= ssp_d;
      retired_q     <= retired_d;
      written_q     <= written_d;
      state_q       <= state_d;
      base_q        <= base_d;
      ib_pc_q       <= ib_pc_d;
      ib_insn_q     <= ib_insn_d;
      ib_pcfault_q  <= ib_pcfault_d;
      ended_q       <= ended_d;
      calli_q       <= calli_d;
      flight_q      <= flight_d;
      sb_q          <= sb_d;
      rr_q          <= rr_d;
      seq_valid_q   <= seq_valid_d;
      seq_chunk_q   <= seq_chunk_d;
      seq_pc_q      <= seq_pc_d;
      seq_insn_q    <= seq_insn_d;
      seq_pcfault_q <= seq_pcfault_d;
      seq_lanes_q   <= seq_lanes_d;
      trace_count_q <= trace_count_d;
      e_q           <= e_d;
    end
  end

`ifndef SYNTHESIS
  // The issue reserves room in the queues, so a hand-off is never refused.
  always_ff @(posedge clk_i or negedge rst_ni) begin : check_queues
    if (rst_ni) begin
      assert (!to_lsu || lsu_in_ready) else $error("rpu_spu: the load/store queue was full");
      assert (!to_sfu || sfu_in_ready) else $error("rpu_spu: the sfu queue was full");
      assert (!to_trace || trace_in_ready) else $error("rpu_spu: the ray queue was full");
      assert (!trace_rsp_valid_i || 32'(trace_rsp_i.tag[rpu_pkg::TraceTagBits-1 -: rpu_pkg::CoreBits]) == CoreId)
        else $error("rpu_spu: a ray answer for core %0d", trace_rsp_i.tag[rpu_pkg::TraceTagBits-1 -: rpu_pkg::CoreBits]);
    end
  end
`endif

endmodule
