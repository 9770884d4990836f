// A shader core (SPU; docs/chip.md "Shader core"): Threads hardware threads in chunks
// of ChunkSize that step in lockstep by the functional model's rule (the smallest live
// pc of a chunk issues, the lanes standing there execute it; docs/shader-core.md).
//
// Per chunk: a state machine picks the next pc, fetches the instruction from the code
// memory and waits until its registers are free (an in-order scoreboard: a count per
// register of the lane writes under way). One chunk instruction is issued at a time,
// round robin among the ready chunks, and its lanes enter the pipeline in lane order,
// IssueLanes a cycle for the instructions of spec/isa.toml [issue] (ALU and branch),
// one a cycle for those handed to a unit (memory, sfu, rays, special registers). The
// pipeline has IssueLanes ways; lane l of a chunk always takes way l % IssueLanes:
//   S0  the lane (or a value returned by the memory, the special-function unit or the
//       ray units, which has priority and the cycle) reads its way's register file bank;
//   E   operands in hand: the checks of spec/isa.toml [[fault]] in their order, the
//       thread's pc, stacks and counters, and hand-offs to the load/store unit, the
//       special-function unit and the ray units; everything else enters the datapath;
//   W   rpu_spu_datapath.Latency cycles later: the register file is written.
// A way's register file is twelve rpu_ram (three read copies x four components), one
// word per thread of the way and register; a register reads as zero until its first
// write, which writes all four components. The trace ports report each chunk step
// (issue), each executed instruction (retire, one port per way), each register write
// (writeback, per way) and each fault, for the lockstep checker (sim/spu_checker.hpp).
module rpu_spu #(
  parameter int unsigned CoreId     = 0,
  parameter int unsigned Cores      = 1,     // on the chip: consecutive chunks of pixels go to consecutive cores (docs/chip.md)
  parameter int unsigned Threads    = 4,
  parameter int unsigned ChunkSize  = 2,
  parameter int unsigned IssueLanes = 1,     // lanes a cycle of spec/isa.toml [issue]'s instructions; divides ChunkSize
  parameter int unsigned Registers  = 32,
  parameter int unsigned CallDepth  = 16,
  parameter int unsigned StackBytes = 16384,
  parameter int unsigned SfuUnits   = 1,
  parameter int unsigned SfuThreads = 1,     // sfus, each one thread at a time; divides ChunkSize
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
  // retire and writeback: one record per way (lane l of a chunk in way l % IssueLanes).
  output logic [IssueLanes-1:0]     retire_valid_o,
  output logic [IssueLanes*rpu_pkg::RetireBits-1:0] retire_o,
  output logic [IssueLanes-1:0]     wb_valid_o,
  output logic [IssueLanes*rpu_pkg::WritebackBits-1:0] wb_o,
  output logic                      fault_valid_o,
  output rpu_pkg::fault_t           fault_o
);

  localparam int unsigned Chunks       = Threads / ChunkSize;
  localparam int unsigned TB           = Threads > 1 ? $clog2(Threads) : 1;
  localparam int unsigned CB           = Chunks > 1 ? $clog2(Chunks) : 1;
  localparam int unsigned LB           = ChunkSize > 1 ? $clog2(ChunkSize) : 1;
  localparam int unsigned RegBits      = rpu_pkg::IsaDstWidth;
  localparam int unsigned BankThreads  = Threads / IssueLanes;  // the threads of one way
  localparam int unsigned RfAddrBits   = $clog2(BankThreads * Registers);
  localparam int unsigned RsAddrBits   = $clog2(BankThreads * CallDepth);
  localparam int unsigned RspBits      = $clog2(CallDepth + 1);
  localparam int unsigned StackSlots   = StackBytes / 16;
  localparam int unsigned SspBits      = $clog2(StackSlots + 1);
  localparam int unsigned CntBits      = $clog2(ChunkSize + 1);
  localparam int unsigned SpinBits     = $clog2(CodeWords + 1);
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
  logic [SpinBits*Threads-1:0]  spin_d, spin_q;     // pc-only instructions retired in a row
  logic [Registers*Threads-1:0] written_d, written_q;
  // Per chunk.
  logic [3*Chunks-1:0]          state_d, state_q;
  logic [32*Chunks-1:0]         base_d, base_q;     // the chunk's first pixel this round: lane l's is base + l
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

  // ---------------------------------------------------------------------------------
  // The code memory (the register file and return stacks are per way, below).
  // ---------------------------------------------------------------------------------
  logic [CodeAddrBits-1:0] code_raddr;
  logic [63:0]             code_rdata;
  rpu_ram #(.Width(64), .Depth(CodeWords)) u_code (
    .clk_i, .we_i(code_we_i), .waddr_i(code_addr_i), .wdata_i(code_data_i),
    .raddr_i(code_raddr), .rdata_o(code_rdata)
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
  // Issue: the sequencer holds one chunk instruction and hands its lanes to S0, a group
  // of IssueLanes lanes a cycle (lane l in way l % IssueLanes) when the instruction is
  // one of spec/isa.toml [issue]'s, else one lane a cycle. Groups go in lane order, so
  // a lane never passes a lower lane of its chunk.
  // ---------------------------------------------------------------------------------
  // A fault in E stops the lanes after it in its chunk (later pixels): those in E with
  // it, in later ways, and those the sequencer has not handed on.
  logic                  kill;
  logic [CB-1:0]         kill_chunk;
  logic [LB-1:0]         kill_lane;
  logic [ChunkSize-1:0]  kill_after;  // the lanes after kill_lane
  logic [ChunkSize-1:0]  seq_live, seq_kill, remaining, group, emit_bits, remaining_after;
  logic                  emit, seq_free, at_once;
  logic [LB-1:0]         first_lane;
  logic [CntBits-1:0]    emit_count;
  logic                  selected;
  logic [CB-1:0]         sel;
  logic                  end_now;       // the sequencer's chunk instruction ends without a last lane
  logic [CB-1:0]         end_now_chunk;

  always_comb begin : next_lanes
    for (int l = 0; l < ChunkSize; l++) begin
      kill_after[l] = kill && LB'(l) > kill_lane;
      seq_live[l]   = live_q[32'(seq_chunk_q) * ChunkSize + l];
      seq_kill[l]   = kill_after[l] && kill_chunk == seq_chunk_q;
    end
    remaining  = seq_valid_q ? seq_lanes_q & seq_live & ~seq_kill : '0;
    emit       = remaining != '0 && !ret_valid;
    first_lane = '0;
    for (int l = ChunkSize - 1; l >= 0; l--) begin
      if (remaining[l]) first_lane = LB'(l);
    end
    at_once    = !seq_pcfault_q && rpu_pkg::isa_at_once(f_op(seq_insn_q)) != 1'b0;
    emit_count = '0;
    for (int l = 0; l < ChunkSize; l++) begin
      group[l]     = at_once ? l / IssueLanes == 32'(first_lane) / IssueLanes : LB'(l) == first_lane;
      emit_bits[l] = emit && remaining[l] && group[l];
      emit_count   = emit_count + CntBits'(emit_bits[l]);
    end
    remaining_after = remaining & ~emit_bits;
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

  // An emitted lane writes the instruction's dst: the scoreboard counts it.
  logic s0_counted;
  assign s0_counted = !seq_pcfault_q && rpu_pkg::isa_writes_dst(f_op(seq_insn_q)) != 1'b0
                      && 32'(f_dst(seq_insn_q)) < Registers;

  // ---------------------------------------------------------------------------------
  // The ways: S0 (register file and return stack reads), E (checks, the thread's
  // effects) and the datapath to W, one per issue lane; thread t always takes way
  // t % IssueLanes, whose banks hold its registers and return addresses. What a lane
  // hands to a unit the core has one of goes from the one way that holds a lane then
  // (the unit way, below): such instructions issue one lane a cycle.
  // ---------------------------------------------------------------------------------
  localparam int unsigned CtrlBits = 3 + TB + RegBits + 4;

  // Per way, side by side.
  logic [IssueLanes-1:0]         e_valid, e_ret, e_inst, e_raw_fault, e_fault, e_exec, e_last, e_calli;
  logic [IssueLanes-1:0]         e_to_lsu, e_to_sfu, e_to_trace, e_setpc, e_pc_only;
  logic [TB*IssueLanes-1:0]      e_thread;
  logic [32*IssueLanes-1:0]      e_pc;
  logic [64*IssueLanes-1:0]      e_insn;
  logic [128*IssueLanes-1:0]     e_src_a, e_src_b, e_c_reg, e_sfu_a;
  logic [SspBits*IssueLanes-1:0] e_ssp_w;
  logic [rpu_pkg::FaultKindBits*IssueLanes-1:0] e_f_kind;
  logic [32*IssueLanes-1:0]      e_f_addr;
  logic [IssueLanes-1:0]         w_write, w_sb_dec, w_fin;
  logic [TB*IssueLanes-1:0]      w_thread;
  logic [RegBits*IssueLanes-1:0] w_dst;
  logic [4*IssueLanes-1:0]       w_wmask;
  logic [128*IssueLanes-1:0]     w_value;   // the lanes written, the others 0
  logic [32*IssueLanes-1:0]      e_addr;    // a memory access's address, for the retire record
  // The effects of way w's lane on its thread.
  logic [32*IssueLanes-1:0]      pc_next;
  logic [IssueLanes-1:0]         pc_we, rsp_push, rsp_pop, ssp_push, ssp_pop, halt;
  logic [Registers*IssueLanes-1:0] written_now;

  // The unit way: the lowest way holding an instruction's lane.
  logic [TB-1:0]         u_thread;
  logic                  u_last;  // the last lane of its chunk's instruction
  logic [31:0]           u_pc;
  logic [63:0]           u_insn;
  logic [127:0]          u_src_a, u_src_b, u_c_reg, u_sfu_a;
  logic [SspBits-1:0]    u_ssp;
  always_comb begin : pick_unit_way
    u_thread = '0;
    u_last   = 1'b0;
    u_pc     = '0;
    u_insn   = '0;
    u_src_a  = '0;
    u_src_b  = '0;
    u_c_reg  = '0;
    u_sfu_a  = '0;
    u_ssp    = '0;
    for (int v = IssueLanes - 1; v >= 0; v--) begin
      if (e_valid[v] && !e_ret[v]) begin
        u_thread = e_thread[TB*v +: TB];
        u_last   = e_last[v];
        u_pc     = e_pc[32*v +: 32];
        u_insn   = e_insn[64*v +: 64];
        u_src_a  = e_src_a[128*v +: 128];
        u_src_b  = e_src_b[128*v +: 128];
        u_c_reg  = e_c_reg[128*v +: 128];
        u_sfu_a  = e_sfu_a[128*v +: 128];
        u_ssp    = e_ssp_w[SspBits*v +: SspBits];
      end
    end
  end

  logic [rpu_pkg::IsaOpcodeWidth-1:0] u_op;
  logic [CB-1:0]        u_chunk;
  logic [LB-1:0]        u_lane;
  logic [31:0]          u_pixel, u_gid, u_imm;
  logic [RegBits-1:0]   u_dst;
  logic [3:0]           u_wmask;
  assign u_op    = f_op(u_insn);
  assign u_chunk = CB'(32'(u_thread) / ChunkSize);
  assign u_lane  = LB'(32'(u_thread) % ChunkSize);
  assign u_gid   = 32'(Thread0) + 32'(u_thread);
  assign u_pixel = base_q[32*u_chunk +: 32] + 32'(u_lane);
  assign u_imm   = u_insn[rpu_pkg::IsaImmLsb +: 32];
  assign u_dst   = f_dst(u_insn);
  assign u_wmask = f_wmask(u_insn);

  // Addresses and their checks: word k of an access at addr + 4k.
  logic [31:0] shader_entry, mem_addr, stack_addr_push, stack_addr_pop, stack_top;
  logic        wide, store;
  logic [3:0]  mem_ok;
  assign shader_entry = launch_i.shader_table + {u_src_a[29:0], 2'b00};
  assign mem_addr     = u_op == rpu_pkg::OpCalli ? shader_entry : u_src_a[31:0] + u_imm;
  assign wide         = u_op == rpu_pkg::OpLd || u_op == rpu_pkg::OpLdf || u_op == rpu_pkg::OpSt;
  assign store        = u_op == rpu_pkg::OpSt || u_op == rpu_pkg::OpSt1;
  // The thread's stack: slot k (1-based) at the top minus 16k; the stacks a line apart
  // (DeviceStackSkew) so that they do not share cache sets and DRAM banks at every depth.
  assign stack_top       = rpu_pkg::DeviceStackBase + u_gid * (StackBytes + rpu_pkg::DeviceStackSkew) + StackBytes;
  assign stack_addr_push = stack_top - ((32'(u_ssp) + 32'd1) << 4);
  assign stack_addr_pop  = stack_top - (32'(u_ssp) << 4);

  for (genvar k = 0; k < 4; k++) begin : g_memcheck
    rpu_spu_memcheck u_check (
      .addr_i(mem_addr + 32'(4 * k)), .bytes_i(k == 0 && wide && !store ? 5'd16 : 5'd4), .write_i(store),
      .pixel_i(u_pixel), .launch_i, .ok_o(mem_ok[k])
    );
  end

  // rdsr pixel: (x, y) of the pixel index by multiplication (launch_t div_magic).
  logic [63:0] div_product;
  logic [31:0] div_t1, div_q, pix_x;
  assign div_product = {32'd0, launch_i.div_magic} * {32'd0, u_pixel};
  assign div_t1      = div_product[63:32];
  logic unused_div;
  assign unused_div = ^div_product[31:0];
  assign div_q       = (div_t1 + ((u_pixel - div_t1) >> launch_i.div_shift1)) >> launch_i.div_shift2;
  assign pix_x       = u_pixel - div_q * launch_i.width;

  logic [127:0] special;
  always_comb begin : special_value
    unique case (u_imm[1:0])
      2'(rpu_pkg::SpecialPixel):  special = {32'd0, u_pixel, div_q, pix_x};
      2'(rpu_pkg::SpecialLaunch): special = {launch_i.max_depth, launch_i.spp, launch_i.height, launch_i.width};
      2'(rpu_pkg::SpecialThread): special = {32'(u_lane), 32'(u_chunk), 32'(CoreId), u_gid};
      default:                    special = {64'd0, launch_i.launch_bytes, rpu_pkg::DeviceLaunchBase};
    endcase
  end

  // The hand-offs: at most one way's lane a cycle.
  logic       to_lsu, to_sfu, to_trace, u_async;
  logic [IssueLanes-1:0] e_async;  // per way: its lane finishes when a value comes back
  logic [3:0] store_words;
  assign to_lsu      = e_to_lsu != '0;
  assign to_sfu      = e_to_sfu != '0;
  assign to_trace    = e_to_trace != '0;
  assign u_async     = e_async != '0;
  assign store_words = u_op == rpu_pkg::OpSt ? u_wmask : u_op == rpu_pkg::OpPush ? 4'b1111 : 4'b0001;

  // S0 and E of every way, side by side (Yosys 0.23 reads no struct inside a generate
  // block): S0 takes the return this way's thread gets, or the sequencer's lane of this
  // way; E holds what S0 had.
  localparam int unsigned OpBits = $bits(ret_op);
  logic [OpBits*IssueLanes-1:0] s0_all, e_all;
  logic [TB*IssueLanes-1:0]     s0_thread;
  logic [64*IssueLanes-1:0]     s0_insn;
  op_t                          s0_lane, e_lane_op;
  always_comb begin : pick_s0
    s0_all    = '0;
    s0_thread = '0;
    s0_insn   = '0;
    for (int v = 0; v < IssueLanes; v++) begin
      s0_lane = '0;
      if (ret_valid) begin
        if (32'(ret_op.thread) % IssueLanes == v) s0_lane = ret_op;
      end else begin
        for (int l = 0; l < ChunkSize; l++) begin
          if (l % IssueLanes == v && emit_bits[l]) begin
            s0_lane.valid   = 1'b1;
            s0_lane.thread  = TB'(32'(seq_chunk_q) * ChunkSize + 32'(l));
            s0_lane.pc      = seq_pc_q;
            s0_lane.insn    = seq_insn_q;
            s0_lane.pcfault = seq_pcfault_q;
            s0_lane.last    = remaining_after == '0;
            s0_lane.counted = s0_counted;
          end
        end
      end
      s0_all[OpBits*v +: OpBits] = s0_lane;
      s0_thread[TB*v +: TB]      = s0_lane.thread;
      s0_insn[64*v +: 64]        = s0_lane.insn;
    end
  end
  always_ff @(posedge clk_i or negedge rst_ni) begin : e_regs
    if (!rst_ni) e_all <= '0;
    else         e_all <= s0_all;
  end
  logic [IssueLanes-1:0]         e_pcfault, e_counted, e_r_round, e_r_widen, e_r_setpc, e_r_tfault;
  logic [RegBits*IssueLanes-1:0] e_r_dst;
  logic [4*IssueLanes-1:0]       e_r_wmask;
  logic [128*IssueLanes-1:0]     e_r_value;
  always_comb begin : unpack_e
    for (int v = 0; v < IssueLanes; v++) begin
      e_lane_op                      = e_all[OpBits*v +: OpBits];
      e_valid[v]                     = e_lane_op.valid;
      e_ret[v]                       = e_lane_op.ret;
      e_thread[TB*v +: TB]           = e_lane_op.thread;
      e_pc[32*v +: 32]               = e_lane_op.pc;
      e_insn[64*v +: 64]             = e_lane_op.insn;
      e_pcfault[v]                   = e_lane_op.pcfault;
      e_last[v]                      = e_lane_op.last;
      e_counted[v]                   = e_lane_op.counted;
      e_r_dst[RegBits*v +: RegBits]  = e_lane_op.r_dst;
      e_r_wmask[4*v +: 4]            = e_lane_op.r_wmask;
      e_r_value[128*v +: 128]        = e_lane_op.r_value;
      e_r_round[v]                   = e_lane_op.r_round;
      e_r_widen[v]                   = e_lane_op.r_widen;
      e_r_setpc[v]                   = e_lane_op.r_setpc;
      e_r_tfault[v]                  = e_lane_op.r_tfault;
    end
  end

  // A register reads as zero until its first write, which writes all four components.
  function automatic logic [127:0] masked(input logic [127:0] v, input logic [Registers*Threads-1:0] wr,
                                          input logic [TB-1:0] t, input logic [RegBits-1:0] r);
    masked = 32'(r) < Registers && wr[Registers*32'(t) + 32'(r)] ? v : '0;
  endfunction
  // Thread t's register r in its way's bank.
  function automatic logic [RfAddrBits-1:0] rf_addr(input logic [TB-1:0] t, input logic [RegBits-1:0] r);
    rf_addr = RfAddrBits'(32'(t) / IssueLanes * Registers + 32'(r));
  endfunction

  for (genvar v = 0; v < IssueLanes; v++) begin : g_way
    // The register file bank: three read copies x four components, one word per thread
    // of the way and register.
    logic                    rf_we;
    logic [3:0]              rf_lane_we;
    logic [RfAddrBits-1:0]   rf_waddr;
    logic [127:0]            rf_wdata;
    logic [3*RfAddrBits-1:0] rf_raddr;
    logic [3*128-1:0]        rf_rdata;
    assign rf_raddr = {rf_addr(s0_thread[TB*v +: TB], f_third(s0_insn[64*v +: 64])), rf_addr(s0_thread[TB*v +: TB], f_b(s0_insn[64*v +: 64])),
                       rf_addr(s0_thread[TB*v +: TB], f_a(s0_insn[64*v +: 64]))};
    for (genvar s = 0; s < 3; s++) begin : g_rf_copy
      for (genvar l = 0; l < 4; l++) begin : g_rf_lane
        rpu_ram #(.Width(32), .Depth(BankThreads * Registers)) u_rf (
          .clk_i, .we_i(rf_we && rf_lane_we[l]), .waddr_i(rf_waddr), .wdata_i(rf_wdata[32*l +: 32]),
          .raddr_i(rf_raddr[RfAddrBits*s +: RfAddrBits]), .rdata_o(rf_rdata[128*s + 32*l +: 32])
        );
      end
    end

    // The return stack bank.
    logic                  rs_we;
    logic [RsAddrBits-1:0] rs_waddr, rs_raddr;
    logic [31:0]           rs_wdata, rs_rdata;
    assign rs_raddr = RsAddrBits'(32'(s0_thread[TB*v +: TB]) / IssueLanes * CallDepth + 32'(rsp_q[RspBits*s0_thread[TB*v +: TB] +: RspBits]) - 1);
    rpu_ram #(.Width(32), .Depth(BankThreads * CallDepth)) u_return_stack (
      .clk_i, .we_i(rs_we), .waddr_i(rs_waddr), .wdata_i(rs_wdata), .raddr_i(rs_raddr), .rdata_o(rs_rdata)
    );

    // E: the op with its operands.
    logic [63:0]          w;
    logic [rpu_pkg::IsaOpcodeWidth-1:0] op;
    logic [RegBits-1:0]   dst;
    logic [3:0]           wmask;
    logic                 mods;
    logic [31:0]          imm;
    logic [127:0]         a_reg, b_reg, c_reg, src_a, src_b, src_c;  // registers as read; swizzled sources
    logic [2:0]           neg, abs;
    logic [RspBits-1:0]   e_rsp;
    logic [SspBits-1:0]   e_ssp;
    logic [31:0]          e_retired;
    logic [SpinBits-1:0]  e_spin;

    assign w         = e_insn[64*v +: 64];
    assign op        = f_op(w);
    assign dst       = e_ret[v] ? e_r_dst[RegBits*v +: RegBits] : f_dst(w);
    assign wmask     = e_ret[v] ? e_r_wmask[4*v +: 4] : f_wmask(w);
    assign mods      = rpu_pkg::isa_format_i(op) == 1'b0;  // R format: neg on a, b, c and abs on a, b
    assign imm       = w[rpu_pkg::IsaImmLsb +: 32];
    assign e_rsp     = rsp_q[RspBits*e_thread[TB*v +: TB] +: RspBits];
    assign e_ssp     = ssp_q[SspBits*e_thread[TB*v +: TB] +: SspBits];
    assign e_retired = retired_q[32*e_thread[TB*v +: TB] +: 32];
    assign e_spin    = spin_q[SpinBits*e_thread[TB*v +: TB] +: SpinBits];
    assign e_pc_only[v] = rpu_pkg::isa_pc_only(op) != 1'b0;

    assign a_reg = masked(rf_rdata[0 +: 128], written_q, e_thread[TB*v +: TB], f_a(w));
    assign b_reg = masked(rf_rdata[128 +: 128], written_q, e_thread[TB*v +: TB], f_b(w));
    assign c_reg = masked(rf_rdata[256 +: 128], written_q, e_thread[TB*v +: TB], f_third(w));
    assign src_a = swizzle(a_reg, w[rpu_pkg::IsaASwizzleLsb +: 8]);
    assign src_b = swizzle(b_reg, w[rpu_pkg::IsaBSwizzleLsb +: 8]);
    assign src_c = swizzle(c_reg, w[rpu_pkg::IsaCSwizzleLsb +: 8]);
    assign neg = mods ? {w[rpu_pkg::IsaCNegLsb], w[rpu_pkg::IsaBNegLsb], w[rpu_pkg::IsaANegLsb]} : 3'b000;
    assign abs = mods ? {1'b0, w[rpu_pkg::IsaBAbsLsb], w[rpu_pkg::IsaAAbsLsb]} : 3'b000;

    assign e_src_a[128*v +: 128]       = src_a;
    assign e_src_b[128*v +: 128]       = src_b;
    assign e_c_reg[128*v +: 128]       = c_reg;
    assign e_ssp_w[SspBits*v +: SspBits] = e_ssp;
    assign e_setpc[v] = e_valid[v] && e_ret[v] && e_r_setpc[v];

    // The checks of spec/isa.toml [[fault]], in their order; those of an access read
    // the unit way's, which is this way whenever the instruction has one.
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
      if (e_ret[v]) begin
        f_any  = e_r_tfault[v];
        f_kind = rpu_pkg::FaultKindBits'(rpu_pkg::FaultTraversal);
      end else if (e_pcfault[v]) begin
        f_kind = rpu_pkg::FaultKindBits'(rpu_pkg::FaultPc);
      end else if (illegal) begin
        f_kind = rpu_pkg::FaultKindBits'(rpu_pkg::FaultIllegal);
      end else if (e_retired >= launch_i.watchdog) begin
        f_kind = rpu_pkg::FaultKindBits'(rpu_pkg::FaultWatchdog);
      end else if (bad_reg) begin
        f_kind = rpu_pkg::FaultKindBits'(rpu_pkg::FaultRegister);
      end else if (e_pc_only[v] && 32'(e_spin) >= launch_i.code_words) begin
        // Its pcs have repeated with nothing else written: it can never end.
        f_kind = rpu_pkg::FaultKindBits'(rpu_pkg::FaultSpin);
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

    // A fault in a lower way of the same cycle stops this lane: it is a later lane of
    // the same chunk instruction.
    logic blocked;
    if (v == 0) begin : g_first
      assign blocked = 1'b0;
    end else begin : g_later
      assign blocked = e_raw_fault[v-1:0] != '0;
    end
    assign e_inst[v]      = e_valid[v] && !e_ret[v];
    assign e_raw_fault[v] = e_valid[v] && f_any;
    assign e_fault[v]     = e_raw_fault[v] && !blocked;
    assign e_exec[v]      = e_inst[v] && !f_any && !blocked;
    assign e_calli[v]     = e_exec[v] && op == rpu_pkg::OpCalli;
    assign e_f_kind[rpu_pkg::FaultKindBits*v +: rpu_pkg::FaultKindBits] = f_kind;
    assign e_f_addr[32*v +: 32] = f_addr;

    // Where the op goes.
    always_comb begin : route_op
      e_to_lsu[v]   = 1'b0;
      e_to_sfu[v]   = 1'b0;
      e_to_trace[v] = 1'b0;
      if (e_exec[v]) begin
        unique case (op)
          rpu_pkg::OpLd, rpu_pkg::OpLdf, rpu_pkg::OpLd1, rpu_pkg::OpLd1f, rpu_pkg::OpPop, rpu_pkg::OpCalli,
          rpu_pkg::OpSt1, rpu_pkg::OpPush: e_to_lsu[v] = 1'b1;
          rpu_pkg::OpSt:                   e_to_lsu[v] = wmask != '0;
          rpu_pkg::OpRcp, rpu_pkg::OpRsq, rpu_pkg::OpSqrt: e_to_sfu[v] = 1'b1;
          rpu_pkg::OpTrace, rpu_pkg::OpTracea: e_to_trace[v] = 1'b1;
          default: ;
        endcase
      end
    end
    // A load, sfu op or ray finishes when its value comes back; a store when it is sent.
    assign e_async[v] = e_to_sfu[v] || e_to_trace[v]
                        || (e_to_lsu[v] && op != rpu_pkg::OpSt && op != rpu_pkg::OpSt1 && op != rpu_pkg::OpPush);

    // The datapath: every op, so that results and the bookkeeping of finished ops come
    // out in order at W.
    logic                wb_valid;
    logic [127:0]        wb_result;
    logic [CtrlBits-1:0] wb_ctrl;
    logic [TB-1:0]       wt;
    logic [RegBits-1:0]  wd;
    logic [3:0]          wm;
    logic                e_write;
    assign e_write = e_ret[v] ? !e_r_tfault[v] && !e_r_setpc[v]
                             : e_exec[v] && !e_async[v] && rpu_pkg::isa_writes_dst(op) != 1'b0;

    rpu_spu_datapath #(.ExpBits(ExpBits), .FracBits(FracBits), .CtrlBits(CtrlBits)) u_datapath (
      .clk_i, .rst_ni,
      .valid_i(e_valid[v]), .op_i(op), .hand_i(e_ret[v]), .hand_round_i(e_r_round[v]), .hand_widen_i(e_r_widen[v]),
      .a_i(e_ret[v] ? e_r_value[128*v +: 128] : src_a), .b_i(src_b), .c_i(src_c), .neg_i(e_ret[v] ? 3'b000 : neg),
      .abs_i(e_ret[v] ? 3'b000 : abs), .imm_i(imm), .raw_i(op == rpu_pkg::OpMfra ? {4{rs_rdata}} : special),
      .ctrl_i({e_write, e_counted[v] && !(e_exec[v] && e_async[v]), e_ret[v] || !(e_exec[v] && e_async[v]), e_thread[TB*v +: TB], dst, wmask}),
      .valid_o(wb_valid), .result_o(wb_result), .ctrl_o(wb_ctrl), .src_a_fmt_o(e_sfu_a[128*v +: 128])
    );
    assign {w_write[v], w_sb_dec[v], w_fin[v], wt, wd, wm} = wb_valid ? wb_ctrl : '0;
    assign w_thread[TB*v +: TB]       = wt;
    assign w_dst[RegBits*v +: RegBits] = wd;

    // W: the register file bank.
    logic w_first;  // the register's first write: the other components become 0
    assign w_first    = !written_q[Registers*32'(wt) + 32'(wd)];
    assign rf_we      = w_write[v];
    assign rf_waddr   = rf_addr(wt, wd);
    assign rf_lane_we = w_first ? 4'b1111 : wm;
    always_comb begin : mask_write_data
      for (int l = 0; l < 4; l++) rf_wdata[32*l +: 32] = wm[l] ? wb_result[32*l +: 32] : '0;
    end
    assign written_now[Registers*v +: Registers] =
        w_write[v] && 32'(wd) < Registers ? Registers'(1) << wd : '0;

    assign wb_valid_o[v] = w_write[v];
    assign w_wmask[4*v +: 4]       = wm;
    assign w_value[128*v +: 128]   = rf_wdata;

    // E's effects on the thread.
    always_comb begin : thread_effects
      pc_next[32*v +: 32] = e_pc[32*v +: 32] + 32'd1;
      pc_we[v]    = e_exec[v] && op != rpu_pkg::OpCalli;
      rsp_push[v] = 1'b0;
      rsp_pop[v]  = 1'b0;
      ssp_push[v] = e_exec[v] && op == rpu_pkg::OpPush;
      ssp_pop[v]  = e_exec[v] && op == rpu_pkg::OpPop;
      halt[v]     = e_exec[v] && op == rpu_pkg::OpHalt;
      rs_we       = 1'b0;
      rs_wdata    = e_pc[32*v +: 32] + 32'd1;
      if (e_exec[v]) begin
        unique case (op)
          rpu_pkg::OpBra: pc_next[32*v +: 32] = imm;
          rpu_pkg::OpBz:  if (src_a[31:0] == '0) pc_next[32*v +: 32] = imm;
          rpu_pkg::OpBnz: if (src_a[31:0] != '0) pc_next[32*v +: 32] = imm;
          rpu_pkg::OpCall: begin
            pc_next[32*v +: 32] = imm;
            rsp_push[v] = 1'b1;
            rs_we       = 1'b1;
          end
          rpu_pkg::OpCalli: begin
            rsp_push[v] = 1'b1;
            rs_we       = 1'b1;
          end
          rpu_pkg::OpMtra: begin
            rsp_push[v] = 1'b1;
            rs_we       = 1'b1;
            rs_wdata    = src_a[31:0];
          end
          rpu_pkg::OpRet: begin
            pc_next[32*v +: 32] = rs_rdata;
            rsp_pop[v] = 1'b1;
          end
          rpu_pkg::OpMfra: rsp_pop[v] = 1'b1;
          default: ;
        endcase
      end
      // calli's entry arrives: the call's target.
      if (e_setpc[v]) begin
        pc_we[v]            = 1'b1;
        pc_next[32*v +: 32] = e_r_value[128*v +: 32];
      end
    end
    assign rs_waddr = RsAddrBits'(32'(e_thread[TB*v +: TB]) / IssueLanes * CallDepth + 32'(e_rsp));

    assign retire_valid_o[v] = e_exec[v];
    assign e_addr[32*v +: 32] =
        !(e_to_lsu[v] || (e_exec[v] && op == rpu_pkg::OpSt)) ? '0
        : op == rpu_pkg::OpPush ? stack_addr_push : op == rpu_pkg::OpPop ? stack_addr_pop : mem_addr;
  end

  // The retire and writeback records, one per way.
  rpu_pkg::retire_t    retire_record;
  rpu_pkg::writeback_t wb_record;
  always_comb begin : trace_records
    for (int v = 0; v < IssueLanes; v++) begin
      retire_record        = '0;
      retire_record.core   = rpu_pkg::CoreBits'(CoreId);
      retire_record.thread = rpu_pkg::ThreadBits'(e_thread[TB*v +: TB]);
      retire_record.pc     = e_pc[32*v +: 32];
      retire_record.insn   = e_insn[64*v +: 64];
      retire_record.addr   = e_addr[32*v +: 32];
      retire_o[rpu_pkg::RetireBits*v +: rpu_pkg::RetireBits] = retire_record;
      wb_record            = '0;
      wb_record.core       = rpu_pkg::CoreBits'(CoreId);
      wb_record.thread     = rpu_pkg::ThreadBits'(w_thread[TB*v +: TB]);
      wb_record.dst        = w_dst[RegBits*v +: RegBits];
      wb_record.wmask      = w_wmask[4*v +: 4];
      wb_record.value      = w_value[128*v +: 128];
      wb_o[rpu_pkg::WritebackBits*v +: rpu_pkg::WritebackBits] = wb_record;
    end
  end

  // The fault: the lowest way's (at most one is not blocked).
  always_comb begin : kill_lanes
    kill       = e_raw_fault != '0;
    kill_chunk = '0;
    kill_lane  = '0;
    fault_o    = '0;
    for (int v = IssueLanes - 1; v >= 0; v--) begin
      if (e_raw_fault[v]) begin
        kill_chunk     = CB'(32'(e_thread[TB*v +: TB]) / ChunkSize);
        kill_lane      = LB'(32'(e_thread[TB*v +: TB]) % ChunkSize);
        fault_o        = '0;
        fault_o.kind   = e_f_kind[rpu_pkg::FaultKindBits*v +: rpu_pkg::FaultKindBits];
        fault_o.core   = rpu_pkg::CoreBits'(CoreId);
        fault_o.thread = rpu_pkg::ThreadBits'(e_thread[TB*v +: TB]);
        fault_o.pixel  = base_q[32*kill_chunk +: 32] + 32'(kill_lane);
        fault_o.pc     = e_pc[32*v +: 32];
        fault_o.addr   = e_f_addr[32*v +: 32];
      end
    end
  end
  assign fault_valid_o = kill;

  // Load/store unit.
  logic lsu_in_ready, lsu_idle;
  rpu_spu_lsu #(.TagBits(LsuTagBits), .Depth(QueueDepth)) u_lsu (
    .clk_i, .rst_ni,
    .in_valid_i(to_lsu), .in_ready_o(lsu_in_ready),
    .in_store_i(store || u_op == rpu_pkg::OpPush),
    .in_tag_i({u_thread, u_dst, u_wmask, u_op == rpu_pkg::OpLd1 || u_op == rpu_pkg::OpLd1f,
               u_op == rpu_pkg::OpLdf || u_op == rpu_pkg::OpLd1f, u_op == rpu_pkg::OpCalli}),
    .in_addr_i(u_op == rpu_pkg::OpPush ? stack_addr_push : u_op == rpu_pkg::OpPop ? stack_addr_pop : mem_addr),
    .in_wide_i(wide || u_op == rpu_pkg::OpPush || u_op == rpu_pkg::OpPop),
    .in_words_i(store_words),
    .in_data_i(u_op == rpu_pkg::OpPush ? u_src_a : u_c_reg),
    .free_o(lsu_free),
    .cache_req_valid_o, .cache_req_ready_i, .cache_req_o,
    .cache_rsp_valid_i, .cache_rsp_ready_o, .cache_rsp_i,
    .out_valid_o(lsu_out_valid), .out_ready_i(lsu_out_ready), .out_tag_o(lsu_out_tag), .out_data_o(lsu_out_data),
    .idle_o(lsu_idle)
  );

  // Special-function units: rcp, rsq, sqrt on the sources in the format. SfuThreads of
  // them, each computing one thread's instruction at a time: chunk lane l's thread goes
  // to sfu l mod SfuThreads. A thread's entry carries its age (the sfus' inputs counted),
  // and of the results ready the oldest goes back first, so the results take S0 in the
  // order their lanes entered when they are ready together. A chunk instruction waits
  // until the fullest sfu has room for it.
  localparam int unsigned SfuSel  = SfuThreads > 1 ? $clog2(SfuThreads) : 1;
  localparam int unsigned AgeBits = $clog2(SfuThreads * QueueDepth) + 1;  // outstanding < 2^(AgeBits-1)
  logic [SfuThreads-1:0]            s_in_valid, s_in_ready, s_out_valid, s_out_ready;
  logic [SfuThreads*(AgeBits+SfuTagBits)-1:0] s_out_tag;
  logic [SfuThreads*128-1:0]        s_out_value;
  logic [SfuThreads*QCountBits-1:0] s_free;
  logic [AgeBits-1:0]               sfu_age_d, sfu_age_q;
  logic [SfuSel-1:0]                sfu_in_sel, sfu_out_sel;
  logic                             sfu_in_ready;

  assign sfu_in_sel = SfuThreads > 1 ? SfuSel'(32'(u_thread) % SfuThreads) : '0;
  assign sfu_in_ready = s_in_ready[sfu_in_sel];
  assign sfu_age_d = to_sfu ? sfu_age_q + AgeBits'(1) : sfu_age_q;
  for (genvar k = 0; k < SfuThreads; k++) begin : g_sfu
    assign s_in_valid[k] = to_sfu && 32'(sfu_in_sel) == k;
    rpu_spu_sfu #(
      .ExpBits(ExpBits), .FracBits(FracBits), .Units(SfuUnits), .Depth(QueueDepth), .TagBits(AgeBits + SfuTagBits)
    ) u_sfu (
      .clk_i, .rst_ni,
      .in_valid_i(s_in_valid[k]), .in_ready_o(s_in_ready[k]), .in_tag_i({sfu_age_q, u_thread, u_dst, u_wmask}),
      .in_op_i(u_op == rpu_pkg::OpRcp ? rpu_pkg::FpOpRcp : u_op == rpu_pkg::OpRsq ? rpu_pkg::FpOpRsqrt : rpu_pkg::FpOpSqrt),
      .in_wmask_i(u_wmask), .in_a_i(u_sfu_a),
      .out_valid_o(s_out_valid[k]), .out_ready_i(s_out_ready[k]),
      .out_tag_o(s_out_tag[(AgeBits+SfuTagBits)*k +: AgeBits+SfuTagBits]),
      .out_value_o(s_out_value[128*k +: 128]),
      .free_o(s_free[QCountBits*k +: QCountBits])
    );
  end

  always_comb begin : pick_sfu
    logic [AgeBits-1:0] age, oldest;
    logic               found;
    sfu_out_sel = '0;
    oldest      = '0;
    found       = 1'b0;
    sfu_free    = s_free[0 +: QCountBits];
    for (int k = 0; k < SfuThreads; k++) begin
      age = s_out_tag[(AgeBits+SfuTagBits)*k + SfuTagBits +: AgeBits];
      // Older: behind the other by less than half the age range.
      if (s_out_valid[k] && (!found || age - oldest >= AgeBits'(1 << (AgeBits - 1)))) begin
        sfu_out_sel = SfuSel'(k);
        oldest      = age;
        found       = 1'b1;
      end
      if (s_free[QCountBits*k +: QCountBits] < sfu_free) sfu_free = s_free[QCountBits*k +: QCountBits];
    end
  end
  assign sfu_out_valid = |s_out_valid;
  assign sfu_out_tag   = s_out_tag[(AgeBits+SfuTagBits)*sfu_out_sel +: SfuTagBits];
  assign sfu_out_value = s_out_value[128*sfu_out_sel +: 128];
  for (genvar k = 0; k < SfuThreads; k++) begin : g_sfu_ready
    assign s_out_ready[k] = sfu_out_ready && 32'(sfu_out_sel) == k;
  end

  // Rays: a queue to the ray units.
  logic                            trace_in_ready;
  rpu_pkg::trace_req_t             trace_in;
  always_comb begin : trace_request
    trace_in           = '0;
    trace_in.tag       = rpu_pkg::TraceTagBits'({rpu_pkg::CoreBits'(CoreId), rpu_pkg::ThreadBits'(u_thread), u_dst, u_wmask});
    trace_in.pc        = u_pc;
    trace_in.origin    = u_src_a[95:0];
    trace_in.t_min     = u_src_a[127:96];
    trace_in.direction = u_src_b[95:0];
    trace_in.t_max     = u_src_b[127:96];
    trace_in.any_hit   = u_op == rpu_pkg::OpTracea;
    trace_in.packet_end = u_last;
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

  // ---------------------------------------------------------------------------------
  // Per-thread state.
  // ---------------------------------------------------------------------------------
  logic [Chunks-1:0] init_chunk;  // the chunk starts a round: its threads start over

  for (genvar t = 0; t < Threads; t++) begin : g_thread
    localparam int unsigned C = t / ChunkSize;
    localparam int unsigned L = t % ChunkSize;
    localparam int unsigned V = t % IssueLanes;  // its way
    logic here;
    assign here = e_valid[V] && 32'(e_thread[TB*V +: TB]) == t;
    always_comb begin : next_thread
      pc_d[32*t +: 32]                  = pc_q[32*t +: 32];
      live_d[t]                         = live_q[t];
      rsp_d[RspBits*t +: RspBits]       = rsp_q[RspBits*t +: RspBits];
      ssp_d[SspBits*t +: SspBits]       = ssp_q[SspBits*t +: SspBits];
      retired_d[32*t +: 32]             = retired_q[32*t +: 32];
      spin_d[SpinBits*t +: SpinBits]    = spin_q[SpinBits*t +: SpinBits];
      written_d[Registers*t +: Registers] = written_q[Registers*t +: Registers];
      if (init_chunk[C]) begin
        pc_d[32*t +: 32]      = launch_i.raygen;
        live_d[t]             = base_q[32*C +: 32] + 32'(t % ChunkSize) < launch_i.pixels;
        rsp_d[RspBits*t +: RspBits] = '0;
        ssp_d[SspBits*t +: SspBits] = '0;
        retired_d[32*t +: 32] = '0;
        spin_d[SpinBits*t +: SpinBits] = '0;
        written_d[Registers*t +: Registers] = '0;
      end else begin
        if (here && pc_we[V]) pc_d[32*t +: 32] = pc_next[32*V +: 32];
        if (here && e_inst[V]) begin
          retired_d[32*t +: 32]          = retired_q[32*t +: 32] + 32'd1;
          spin_d[SpinBits*t +: SpinBits] = e_pc_only[V] ? spin_q[SpinBits*t +: SpinBits] + SpinBits'(1) : '0;
        end
        if (here && rsp_push[V]) rsp_d[RspBits*t +: RspBits] = rsp_q[RspBits*t +: RspBits] + RspBits'(1);
        if (here && rsp_pop[V]) rsp_d[RspBits*t +: RspBits] = rsp_q[RspBits*t +: RspBits] - RspBits'(1);
        if (here && ssp_push[V]) ssp_d[SspBits*t +: SspBits] = ssp_q[SspBits*t +: SspBits] + SspBits'(1);
        if (here && ssp_pop[V]) ssp_d[SspBits*t +: SspBits] = ssp_q[SspBits*t +: SspBits] - SspBits'(1);
        if (here && (halt[V] || e_fault[V])) live_d[t] = 1'b0;
        if (kill_after[L] && 32'(kill_chunk) == C) live_d[t] = 1'b0;
        if (32'(w_thread[TB*V +: TB]) == t) begin
          written_d[Registers*t +: Registers] = written_q[Registers*t +: Registers] | written_now[Registers*V +: Registers];
        end
      end
    end
  end

  // ---------------------------------------------------------------------------------
  // Per-chunk state.
  // ---------------------------------------------------------------------------------
  logic [Chunks-1:0] chunk_end;
  always_comb begin : find_chunk_ends
    chunk_end = '0;
    for (int v = 0; v < IssueLanes; v++) begin
      if (e_inst[v] && (e_last[v] || e_fault[v])) chunk_end[32'(e_thread[TB*v +: TB]) / ChunkSize] = 1'b1;
    end
    if (end_now) chunk_end[end_now_chunk] = 1'b1;
  end

  for (genvar c = 0; c < Chunks; c++) begin : g_chunk
    // Block b of ChunkSize pixels runs in round b / (Cores x Chunks) on chunk
    // b mod (Cores x Chunks) / Cores of core b mod Cores: neighbouring blocks on
    // neighbouring cores, so every core sees every part of the image.
    localparam int unsigned FirstPixel = (c * Cores + CoreId) * ChunkSize;
    logic [31:0] first_pixel, next_base;
    logic        refuse;
    logic [CntBits-1:0] s0_lanes;  // this chunk's lanes entering S0
    logic [CntBits-1:0] w_fins;    // its lanes finishing at W
    logic               calli_out, calli_back;
    assign first_pixel = base_q[32*c +: 32];
    assign refuse      = first_pixel >= launch_i.pixels || (stop_i && first_pixel > stop_pixel_i);
    assign next_base   = base_q[32*c +: 32] + 32'(TotalThreads);
    assign s0_lanes    = seq_chunk_q == CB'(c) ? emit_count : '0;
    assign init_chunk[c] = state_q[3*c +: 3] == CStart && !refuse;

    always_comb begin : chunk_ways
      w_fins     = '0;
      calli_out  = 1'b0;
      calli_back = 1'b0;
      for (int v = 0; v < IssueLanes; v++) begin
        if (w_fin[v] && 32'(w_thread[TB*v +: TB]) / ChunkSize == c) w_fins = w_fins + CntBits'(1);
        if (32'(e_thread[TB*v +: TB]) / ChunkSize == c) begin
          calli_out  = calli_out || e_calli[v];
          calli_back = calli_back || e_setpc[v];
        end
      end
    end

    always_comb begin : next_chunk
      state_d[3*c +: 3]           = state_q[3*c +: 3];
      base_d[32*c +: 32]          = base_q[32*c +: 32];
      ib_pc_d[32*c +: 32]         = ib_pc_q[32*c +: 32];
      ib_insn_d[64*c +: 64]       = ib_insn_q[64*c +: 64];
      ib_pcfault_d[c]             = ib_pcfault_q[c];
      ended_d[c]                  = ended_q[c] || chunk_end[c];
      calli_d[CntBits*c +: CntBits] = calli_q[CntBits*c +: CntBits] + CntBits'(calli_out) - CntBits'(calli_back);
      flight_d[FlightBits*c +: FlightBits] = flight_q[FlightBits*c +: FlightBits]
          + FlightBits'(s0_lanes) - FlightBits'(w_fins);

      unique case (state_q[3*c +: 3])
        CIdle: if (start_i) begin
          state_d[3*c +: 3]  = CStart;
          base_d[32*c +: 32] = 32'(FirstPixel);
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
      logic [CntBits-1:0] inc, dec;
      assign inc = s0_counted && 32'(f_dst(seq_insn_q)) == r ? s0_lanes : '0;
      always_comb begin : count_writes_back
        dec = '0;
        for (int v = 0; v < IssueLanes; v++) begin
          if (w_sb_dec[v] && 32'(w_thread[TB*v +: TB]) / ChunkSize == c && 32'(w_dst[RegBits*v +: RegBits]) == r) begin
            dec = dec + CntBits'(1);
          end
        end
      end
      assign sb_d[CntBits*(Registers*c + r) +: CntBits] = sb_q[CntBits*(Registers*c + r) +: CntBits] + inc - dec;
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
    logic u_here, ray_out, ray_back, load_out, load_back_here, live;
    assign u_here         = 32'(u_chunk) == c;
    assign ray_out        = u_here && to_trace;
    assign load_out       = u_here && to_lsu && u_async;
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
      spin_q        <= '0;
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
      sfu_age_q     <= '0;
    end else begin
      pc_q          <= pc_d;
      live_q        <= live_d;
      rsp_q         <= rsp_d;
      ssp_q         <= ssp_d;
      retired_q     <= retired_d;
      spin_q        <= spin_d;
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
      sfu_age_q     <= sfu_age_d;
    end
  end

`ifndef SYNTHESIS
  // The issue reserves room in the queues, so a hand-off is never refused; lanes handed
  // to a unit issue one a cycle.
  always_ff @(posedge clk_i or negedge rst_ni) begin : check_queues
    if (rst_ni) begin
      assert (!to_lsu || lsu_in_ready) else $error("rpu_spu: the load/store queue was full");
      assert (!to_sfu || sfu_in_ready) else $error("rpu_spu: the sfu queue was full");
      assert (ChunkSize % SfuThreads == 0) else $error("rpu_spu: %0d sfus do not divide chunks of %0d", SfuThreads, ChunkSize);
      assert (!to_trace || trace_in_ready) else $error("rpu_spu: the ray queue was full");
      assert ($countones({e_to_lsu, e_to_sfu, e_to_trace}) <= 1)
        else $error("rpu_spu: two lanes handed to units in one cycle");
      assert (!trace_rsp_valid_i || 32'(trace_rsp_i.tag[rpu_pkg::TraceTagBits-1 -: rpu_pkg::CoreBits]) == CoreId)
        else $error("rpu_spu: a ray answer for core %0d", trace_rsp_i.tag[rpu_pkg::TraceTagBits-1 -: rpu_pkg::CoreBits]);
    end
  end
`endif

endmodule
