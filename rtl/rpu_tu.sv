// The traversal unit: docs/traversal.md §1-§3 and §6 for one ray at a time, bit for bit
// the sequence of rpu::functional::Tracer::trace_with. Every rounded operation runs on
// the FP units (rpu_fp_fma: sub, mul; rpu_fp_misc: the compares and the fp32
// conversions; rpu_fp_divsqrt: rcp, div); the unit itself only moves values, tests sign
// bits and keeps the kd walk's state. Ray/triangle tests go out on the IU port.
//
// Sequencing: each state issues at most one op per FP unit, tagged with where its
// result goes (a value register, a flag, or an output word); results are written when
// they come back. A state that needs earlier results waits until none are in flight.
// The FP units never stall here (every response is taken at once), so the cycles the
// unit spends besides waiting for memory and the IU are fixed per step kind
// (docs/rtl.md, "Traversal unit", defines and lists them).
//
// Memory: one 16-byte line per request, responses in request order; a node is one
// line, a prim ref one line, an intersection record three (requested back to back).
// A ray whose walk pushes onto a full stack ends with fault set (Tracer's "traversal
// stack overflow" error).
//
// HandOff = 1 makes the unit a set-up engine of rpu_tu_pipe: a ray whose clipped
// interval is not empty leaves on the start port after StClipEnd instead of walking
// (start_ray_o: the ray as the IU sees it, t_best = t_max); defined misses and rays
// that miss the box answer on rsp as always. The walk's states are then never entered.
module rpu_tu #(
  parameter int unsigned ExpBits    = rpu_pkg::FormatFp32ExponentBits,
  parameter int unsigned FracBits   = rpu_pkg::FormatFp32FractionBits,
  parameter int unsigned IsectMode  = rpu_pkg::IsectModeWoop,
  parameter int unsigned StackDepth = rpu_pkg::ConfigDefaultStackDepth,
  parameter bit          HandOff    = 1'b0
) (
  input  logic              clk_i,
  input  logic              rst_ni,

  input  rpu_pkg::tu_cfg_t  cfg_i,

  input  logic              req_valid_i,
  output logic              req_ready_o,
  input  rpu_pkg::tu_req_t  req_i,

  output logic              rsp_valid_o,
  input  logic              rsp_ready_i,
  output rpu_pkg::tu_rsp_t  rsp_o,

  output logic              mem_req_valid_o,
  input  logic              mem_req_ready_i,
  output rpu_pkg::mem_req_t mem_req_o,

  input  logic              mem_rsp_valid_i,
  output logic              mem_rsp_ready_o,
  input  rpu_pkg::mem_rsp_t mem_rsp_i,

  output logic              iu_req_valid_o,
  input  logic              iu_req_ready_i,
  output rpu_pkg::iu_req_t  iu_req_o,

  input  logic              iu_rsp_valid_i,
  output logic              iu_rsp_ready_o,
  input  rpu_pkg::iu_rsp_t  iu_rsp_i,

  // HandOff = 1: the set-up ray; inv, t_near and t_far in the format, right-aligned.
  output logic              start_valid_o,
  input  logic              start_ready_i,
  output rpu_pkg::iu_req_t  start_ray_o,
  output logic [3*32-1:0]   start_inv_o,
  output logic [31:0]       start_t_near_o,
  output logic [31:0]       start_t_far_o,
  output logic              start_any_hit_o,
  output logic [2:0]        start_dir_le0_o  // D[axis] <= 0, which orders a node's children
);

  localparam int unsigned W = 1 + ExpBits + FracBits;
  localparam bit Watertight = IsectMode == rpu_pkg::IsectModeWatertight;
  localparam logic [W-1:0] Zero = '0;
  localparam logic [W-1:0] Inf = {1'b0, {ExpBits{1'b1}}, {FracBits{1'b0}}};
  localparam logic [W-1:0] AbsMask = {1'b0, {(W - 1){1'b1}}};
  localparam int unsigned TagBits = rpu_pkg::FpTagBits;
  localparam int unsigned IndexBits = rpu_pkg::KdNodeIndexBits;
  localparam int unsigned EntryBits = IndexBits + 2 * W;
  localparam int unsigned SpBits = $clog2(StackDepth + 1);
  // The image's record layouts (spec/memory_map.toml): an intersection record of this
  // mode arrives as whole memory lines, counted in SentBits.
  localparam int unsigned RecordBytes = Watertight ? rpu_pkg::TriangleRecordWatertightBytes
                                                   : rpu_pkg::TriangleRecordWoopBytes;
  localparam int unsigned RecordLines = RecordBytes / rpu_pkg::MemLineBytes;
  localparam int unsigned LineBits = 8 * rpu_pkg::MemLineBytes;
  // A line's byte offset and the word it selects; a node (two words) and a ref (one)
  // lie inside one line, since their sizes divide MemLineBytes.
  localparam int unsigned OffsetBits = $clog2(rpu_pkg::MemLineBytes);
  localparam int unsigned WordSelBits = OffsetBits - 2;
  localparam int unsigned SentBits = $clog2(RecordLines + 1);

  // Value registers (format values). The first 14 are loaded in this order from the
  // request and the box (StLoad's step = register index).
  localparam int unsigned RegBits = 5;
  localparam int unsigned NumRegs = 32;
  localparam logic [RegBits-1:0] RO = 0, RD = 3, RTMin = 6, RTMax = 7, RLo = 8,
                                 RInv = 14, RTNear = 17, RTFar = 18, RTBest = 19, RSx = 20,
                                 RSy = 21, RBox = 22, RSplit = 28, RTSplit = 29, RHitU = 30,
                                 RHitV = 31;
  // Flags: compare results.
  localparam int unsigned NumFlags = 32;
  localparam logic [4:0] FOFin = 0, FDFin = 3, FDZero = 6, FInterval = 9, FDLe0 = 10,
                         FYX = 13, FZX = 14, FZY = 15, FKzNeg = 16, FEntry = 17, FExit = 18,
                         FNearFar = 19, FOLt = 20, FOEq = 21, FSplitLeFar = 22,
                         FSplitLe0 = 23, FSplitLtNear = 24, FBestLeFar = 25, FBestLtNear = 26;
  // Where an FP result goes: tag[7:6] = kind, tag[4:0] = index.
  localparam logic [1:0] DstReg = 2'd0, DstFlag = 2'd1, DstOut = 2'd2;

  typedef enum logic [4:0] {
    StIdle,       // waiting for a ray
    StLoad,       // §1: round the 8 ray values and the 6 box values into the format
    StCheck,      // §1: defined-miss tests, the watertight axis compares; §2: box - O
    StValid,      // §1: a defined miss ends here; watertight: sign of D[kz]
    StRcp,        // §1: inv = rcp(D); watertight: shear_x, shear_y
    StClipMul,    // §2: (box - O) * inv
    StClipEntry,  // §2: entry > t_near
    StClipExit,   // §2: exit < t_far
    StClipUpdate, // §2: narrow the interval
    StClipTest,   // §2: t_near <= t_far
    StClipEnd,
    StNodeReq,    // §3: fetch a node
    StNodeWait,
    StInner,      // §3: an inner node, steps 0..6
    StInnerEnd,
    StLeafNext,   // §3: fetch the next prim ref, or end the list
    StRefWait,
    StRecord,     // §3: fetch the intersection record
    StIuReq,      // §3: one IU test
    StIuWait,
    StLeafEnd,    // §3: t_best <= t_far of this leaf
    StLeafDecide,
    StPop,        // §3: t_best < t_near of the popped entry
    StPopDecide,
    StFinish,     // §6: widen t, u, v to fp32
    StRsp,        // the response
    StHandOff     // HandOff: the set-up ray leaves on the start port
  } state_e;

  // --- The request, through a skid buffer (registered ready). ---
  logic             ray_valid, ray_ready;
  rpu_pkg::tu_req_t ray_in;

  rpu_skid_buf #(.Width($bits(req_i))) u_req_buf (
    .clk_i, .rst_ni,
    .valid_i(req_valid_i), .ready_o(req_ready_o), .data_i(req_i),
    .valid_o(ray_valid), .ready_i(ray_ready), .data_o(ray_in)
  );

  // --- State. ---
  state_e                  state_d, state_q;
  logic [4:0]              step_d, step_q;
  rpu_pkg::tu_req_t        ray_d, ray_q;
  logic [NumRegs*W-1:0]    regs_d, regs_q;
  logic [NumFlags-1:0]     flags_d, flags_q;
  logic [3*32-1:0]         out_d, out_q;       // t, u, v widened to fp32
  logic [1:0]              kz_d, kz_q;
  logic [1:0]              axis_d, axis_q;     // clip axis, or the inner node's split axis
  logic [IndexBits-1:0]    node_d, node_q, above_d, above_q, count_d, count_q, k_d, k_q;
  logic [31:0]             split_d, split_q, first_d, first_q, prim_d, prim_q;
  logic [31:0]             hit_prim_d, hit_prim_q;
  logic                    hit_d, hit_q, fault_d, fault_q;
  logic [WordSelBits-1:0]  half_d, half_q;     // word of the line a node or ref sits at
  logic [SentBits-1:0]     sent_d, sent_q, got_d, got_q;
  logic [rpu_pkg::IsectRecordWords*32-1:0] record_d, record_q;
  logic [StackDepth*EntryBits-1:0] stack_d, stack_q;
  logic [SpBits-1:0]       sp_d, sp_q;
  logic [31:0]             nodes_d, nodes_q, leaves_d, leaves_q, tests_d, tests_q;
  logic [2:0]              fm_busy_d, fm_busy_q;  // fma + misc ops in flight (at most 4)
  logic                    div_busy_d, div_busy_q;

  // The state machine's writes to the register file, the stack and the record: enables
  // and values that the continuous assignments below the state machine apply (Yosys
  // 0.23's proc_mux takes minutes on variable part-select writes in a process).
  logic                    near_we, far_we, best_we, uv_we, push, record_we;
  logic [W-1:0]            near_wd, far_wd, best_wd;

  // Register reads (a function on the flat vector: Yosys 0.23 turns an array of
  // them into a memory and warns).
  function automatic logic [W-1:0] rd(input logic [NumRegs*W-1:0] file, input logic [RegBits-1:0] index);
    rd = file[index*W +: W];
  endfunction

  // The watertight axes (§5 set-up): kx, ky follow kz, swapped when D[kz] < 0.
  logic [1:0] kz_pick, kx, ky, kz_next, kz_next2;
  assign kz_pick  = flags_q[FYX] && flags_q[FZX] ? 2'd0 : flags_q[FZY] ? 2'd1 : 2'd2;
  assign kz_next  = kz_q == 2'd2 ? 2'd0 : kz_q + 2'd1;
  assign kz_next2 = kz_next == 2'd2 ? 2'd0 : kz_next + 2'd1;
  assign kx = flags_q[FKzNeg] ? kz_next2 : kz_next;
  assign ky = flags_q[FKzNeg] ? kz_next : kz_next2;

  // §2: the planes of the clip axis, ordered by the sign bit of inv.
  logic [RegBits-1:0] entry_reg, exit_reg;
  logic [W-1:0]       clip_inv;
  logic               inv_negative;
  assign clip_inv     = rd(regs_q, RInv + RegBits'(axis_q));
  assign inv_negative = clip_inv[W-1];
  assign entry_reg = RBox + RegBits'(axis_q) + (inv_negative ? RegBits'(3) : RegBits'(0));
  assign exit_reg  = RBox + RegBits'(axis_q) + (inv_negative ? RegBits'(0) : RegBits'(3));

  // Kd space (docs/traversal.md §1, §6): the image's geometry is world space times 2^-s;
  // the origin and the interval move there before rounding, the hit distance back.
  logic signed [9:0] to_world_exp, to_kd_exp;
  logic [3*32-1:0]   kd_origin;
  logic [31:0]       kd_t_min, kd_t_max, world_t;
  assign to_world_exp = {{2{cfg_i.kd_scale_exponent[7]}}, cfg_i.kd_scale_exponent};
  assign to_kd_exp    = -to_world_exp;
  for (genvar i = 0; i < 3; i++) begin : g_kd_origin
    rpu_fp32_scale u_origin (
      .value_i(ray_q.origin[32*i +: 32]), .exp_i(to_kd_exp), .value_o(kd_origin[32*i +: 32])
    );
  end
  rpu_fp32_scale u_t_min (.value_i(ray_q.t_min), .exp_i(to_kd_exp), .value_o(kd_t_min));
  rpu_fp32_scale u_t_max (.value_i(ray_q.t_max), .exp_i(to_kd_exp), .value_o(kd_t_max));
  rpu_fp32_scale u_t_out (.value_i(out_q[0 +: 32]), .exp_i(to_world_exp), .value_o(world_t));

  // The raw fp32 words StLoad rounds: origin, direction, t_min, t_max, box lo, box hi.
  logic [14*32-1:0] raw;
  assign raw = {cfg_i.bounds_hi, cfg_i.bounds_lo, kd_t_max, kd_t_min, ray_q.direction, kd_origin};

  // --- The FP units. ---
  logic             fma_valid, misc_valid, div_valid, div_ready;
  rpu_pkg::fp_req_t fma_req, misc_req, div_req;
  logic             fma_rsp_valid, misc_rsp_valid, div_rsp_valid;
  rpu_pkg::fp_rsp_t fma_rsp, misc_rsp, div_rsp;
  logic             fma_ready_unused, misc_ready_unused;

  rpu_fp_fma #(.ExpBits(ExpBits), .FracBits(FracBits)) u_fma (
    .clk_i, .rst_ni, .req_valid_i(fma_valid), .req_ready_o(fma_ready_unused), .req_i(fma_req),
    .rsp_valid_o(fma_rsp_valid), .rsp_ready_i(1'b1), .rsp_o(fma_rsp)
  );
  rpu_fp_misc #(.ExpBits(ExpBits), .FracBits(FracBits)) u_misc (
    .clk_i, .rst_ni, .req_valid_i(misc_valid), .req_ready_o(misc_ready_unused), .req_i(misc_req),
    .rsp_valid_o(misc_rsp_valid), .rsp_ready_i(1'b1), .rsp_o(misc_rsp)
  );
  rpu_fp_divsqrt #(.ExpBits(ExpBits), .FracBits(FracBits)) u_div (
    .clk_i, .rst_ni, .req_valid_i(div_valid), .req_ready_o(div_ready), .req_i(div_req),
    .rsp_valid_o(div_rsp_valid), .rsp_ready_i(1'b1), .rsp_o(div_rsp)
  );

  // Request and operand helpers.
  // (A vector, not the struct: Yosys 0.23 reads no struct-typed functions.)
  localparam int unsigned FpReqBits = rpu_pkg::FpOpBits + TagBits + 3 * rpu_pkg::FpOperandBits;
  function automatic logic [FpReqBits-1:0] fp_op(input rpu_pkg::fp_op_e op, input logic [1:0] kind,
                                                 input logic [4:0] index, input logic [31:0] a,
                                                 input logic [31:0] b);
    fp_op = {op, kind, 1'b0, index, a, b, 32'b0};
  endfunction

  function automatic logic [31:0] ext(input logic [W-1:0] value);
    ext = 32'(value);
  endfunction

  function automatic logic [W-1:0] abs_of(input logic [W-1:0] value);
    abs_of = value & AbsMask;
  endfunction

  // The ops the state machine issues: op, destination and operand selects, assembled
  // into the requests by continuous assignments (function calls inside the state
  // machine's process made Yosys 0.23's proc_mux take many minutes). An operand select
  // is {abs, source, index}: a register (abs clears its sign bit), a constant (0, Inf),
  // a raw fp32 word of StLoad, or the node's split word.
  localparam int unsigned SelBits = 8;
  localparam logic [1:0] SrcReg = 2'd0, SrcConst = 2'd1, SrcRaw = 2'd2, SrcSplit = 2'd3;
  localparam logic [SelBits-1:0] SrcZero = {1'b0, SrcConst, 5'd0}, SrcInf = {1'b0, SrcConst, 5'd1};
  rpu_pkg::fp_op_e    fma_op, misc_op, div_op;
  logic [1:0]         misc_kind;
  logic [4:0]         fma_dst, misc_dst, div_dst;
  logic [SelBits-1:0] fma_a, fma_b, misc_a, misc_b, div_a, div_b;

  function automatic logic [31:0] operand(input logic [SelBits-1:0] sel, input logic [NumRegs*W-1:0] file,
                                          input logic [14*32-1:0] words, input logic [31:0] split);
    operand = sel[6:5] == SrcReg   ? ext(sel[7] ? abs_of(rd(file, sel[4:0])) : rd(file, sel[4:0]))
            : sel[6:5] == SrcConst ? (sel[0] ? ext(Inf) : ext(Zero))
            : sel[6:5] == SrcRaw   ? words[sel[3:0]*32 +: 32]
            : split;
  endfunction

  assign fma_req  = fp_op(fma_op, DstReg, fma_dst, operand(fma_a, regs_q, raw, split_q),
                          operand(fma_b, regs_q, raw, split_q));
  assign misc_req = fp_op(misc_op, misc_kind, misc_dst, operand(misc_a, regs_q, raw, split_q),
                          operand(misc_b, regs_q, raw, split_q));
  assign div_req  = fp_op(div_op, DstReg, div_dst, operand(div_a, regs_q, raw, split_q),
                          operand(div_b, regs_q, raw, split_q));

  // Addresses: records of the spec's sizes (a node, a ref, this mode's intersection
  // record, the latter fetched line by line), modulo 2^32.
  logic [31:0] node_addr, ref_addr, record_addr;
  assign node_addr   = cfg_i.kd_nodes + 32'(node_q) * rpu_pkg::KdNodeBytes;
  assign ref_addr    = cfg_i.prim_refs + (first_q + 32'(k_q)) * rpu_pkg::PrimRefBytes;
  assign record_addr = cfg_i.isect_records + prim_q * RecordBytes + 32'(sent_q) * rpu_pkg::MemLineBytes;

  logic [31:0] line_word, next_word;  // the word half_q selects in the line, and the next
  logic [WordSelBits-1:0] next_half;
  assign next_half = half_q + WordSelBits'(1);
  assign line_word = mem_rsp_i.data[32*half_q +: 32];
  assign next_word = mem_rsp_i.data[32*next_half +: 32];

  // The stack's top entry.
  logic [EntryBits-1:0] top;
  assign top = sp_q == '0 ? '0 : stack_q[(32'(sp_q) - 32'd1)*EntryBits +: EntryBits];

  // Inner node: the children in visiting order.
  logic                 below_first;
  logic [IndexBits-1:0] first_child, second_child;
  assign below_first  = flags_q[FOLt] || (flags_q[FOEq] && flags_q[FDLe0 + 5'(axis_q)]);
  assign first_child  = below_first ? node_q + IndexBits'(1) : above_q;
  assign second_child = below_first ? above_q : node_q + IndexBits'(1);

  // The answer's and the hand-off's valid follow the state alone, outside the process
  // below that reads their readies: an arbiter that grants by them (rpu_tu_pipe's)
  // closes no combinational loop through it.
  assign rsp_valid_o   = state_q == StRsp && fm_busy_q == '0;
  assign start_valid_o = state_q == StHandOff;

  always_comb begin : walk_fsm
    state_d    = state_q;
    step_d     = step_q;
    ray_d      = ray_q;
    kz_d       = kz_q;
    axis_d     = axis_q;
    node_d     = node_q;
    above_d    = above_q;
    count_d    = count_q;
    k_d        = k_q;
    split_d    = split_q;
    first_d    = first_q;
    prim_d     = prim_q;
    hit_prim_d = hit_prim_q;
    hit_d      = hit_q;
    fault_d    = fault_q;
    half_d     = half_q;
    sent_d     = sent_q;
    got_d      = got_q;
    sp_d       = sp_q;
    nodes_d    = nodes_q;
    leaves_d   = leaves_q;
    tests_d    = tests_q;

    near_we         = 1'b0;
    far_we          = 1'b0;
    best_we         = 1'b0;
    uv_we           = 1'b0;
    push            = 1'b0;
    record_we       = 1'b0;

    ray_ready       = 1'b0;
    fma_valid       = 1'b0;
    misc_valid      = 1'b0;
    div_valid       = 1'b0;
    fma_op          = rpu_pkg::FpOpSub;
    fma_dst         = '0;
    fma_a           = SrcZero;
    fma_b           = SrcZero;
    misc_op         = rpu_pkg::FpOpLt;
    misc_kind       = DstFlag;
    misc_dst        = '0;
    misc_a          = SrcZero;
    misc_b          = SrcZero;
    div_op          = rpu_pkg::FpOpRcp;
    div_dst         = '0;
    div_a           = SrcZero;
    div_b           = SrcZero;
    mem_req_valid_o = 1'b0;
    mem_req_o.tag   = '0;  // answered in order
    mem_req_o.addr  = {node_addr[31:OffsetBits], OffsetBits'(0)};
    mem_rsp_ready_o = 1'b0;
    iu_req_valid_o  = 1'b0;
    iu_rsp_ready_o  = 1'b0;

    unique case (state_q)
      StIdle: begin
        ray_ready = 1'b1;
        if (ray_valid) begin
          ray_d    = ray_in;
          step_d   = '0;
          hit_d    = 1'b0;
          fault_d  = 1'b0;
          sp_d     = '0;
          nodes_d  = '0;
          leaves_d = '0;
          tests_d  = '0;
          state_d  = StLoad;
        end
      end

      StLoad: begin
        misc_valid = 1'b1;
        misc_op = rpu_pkg::FpOpFromFp32;
        misc_kind = DstReg;
        misc_dst = step_q;
        misc_a = {1'b0, SrcRaw, step_q};
        misc_b = SrcZero;
        step_d = step_q + 5'd1;
        if (step_q == 5'd13) begin
          step_d  = '0;
          state_d = StCheck;
        end
      end

      // Compares on misc, box - O on fma (both needed only by a valid ray, but issuing
      // them for every ray keeps the schedule fixed).
      StCheck: begin
        if (fm_busy_q == '0 || step_q != '0) begin
          misc_valid = 1'b1;
          if (step_q < 5'd3) begin
            misc_op = rpu_pkg::FpOpLt;
            misc_kind = DstFlag;
            misc_dst = FOFin + step_q;
            misc_a = {1'b1, SrcReg, RegBits'(RO + step_q)};
            misc_b = SrcInf;
          end else if (step_q < 5'd6) begin
            misc_op = rpu_pkg::FpOpLt;
            misc_kind = DstFlag;
            misc_dst = FDFin + step_q - 5'd3;
            misc_a = {1'b1, SrcReg, RegBits'(RD + step_q - 5'd3)};
            misc_b = SrcInf;
          end else if (step_q < 5'd9) begin
            misc_op = rpu_pkg::FpOpEq;
            misc_kind = DstFlag;
            misc_dst = FDZero + step_q - 5'd6;
            misc_a = {1'b0, SrcReg, RegBits'(RD + step_q - 5'd6)};
            misc_b = SrcZero;
          end else if (step_q == 5'd9) begin
            misc_op = rpu_pkg::FpOpLt;
            misc_kind = DstFlag;
            misc_dst = FInterval;
            misc_a = {1'b0, SrcReg, RTMin};
            misc_b = {1'b0, SrcReg, RTMax};
          end else if (step_q < 5'd13) begin
            misc_op = rpu_pkg::FpOpLe;
            misc_kind = DstFlag;
            misc_dst = FDLe0 + step_q - 5'd10;
            misc_a = {1'b0, SrcReg, RegBits'(RD + step_q - 5'd10)};
            misc_b = SrcZero;
          end else if (step_q == 5'd13) begin
            misc_op = rpu_pkg::FpOpLe;
            misc_kind = DstFlag;
            misc_dst = FYX;
            misc_a = {1'b1, SrcReg, RD + RegBits'(1)};
            misc_b = {1'b1, SrcReg, RD};
          end else if (step_q == 5'd14) begin
            misc_op = rpu_pkg::FpOpLe;
            misc_kind = DstFlag;
            misc_dst = FZX;
            misc_a = {1'b1, SrcReg, RD + RegBits'(2)};
            misc_b = {1'b1, SrcReg, RD};
          end else begin
            misc_op = rpu_pkg::FpOpLe;
            misc_kind = DstFlag;
            misc_dst = FZY;
            misc_a = {1'b1, SrcReg, RD + RegBits'(2)};
            misc_b = {1'b1, SrcReg, RD + RegBits'(1)};
          end
          if (step_q < 5'd6) begin
            fma_valid = 1'b1;
            fma_op = rpu_pkg::FpOpSub;
            fma_dst = RBox + step_q;
            fma_a = {1'b0, SrcReg, RegBits'(RLo + step_q)};
            fma_b = {1'b0, SrcReg, RegBits'(RO + (step_q < 5'd3 ? step_q : step_q - 5'd3))};
          end
          step_d = step_q + 5'd1;
          if (step_q == (Watertight ? 5'd15 : 5'd12)) begin
            step_d  = '0;
            state_d = StValid;
          end
        end
      end

      StValid: begin
        if (fm_busy_q == '0) begin
          if (!(&flags_q[FOFin +: 6]) || (&flags_q[FDZero +: 3]) || !flags_q[FInterval]) begin
            state_d = StRsp;  // a defined miss: nothing fetched
          end else begin
            near_we = 1'b1;
            far_we  = 1'b1;
            best_we = 1'b1;
            kz_d = kz_pick;
            if (Watertight) begin
              misc_valid = 1'b1;
              misc_op = rpu_pkg::FpOpLt;
              misc_kind = DstFlag;
              misc_dst = FKzNeg;
              misc_a = {1'b0, SrcReg, RegBits'(RD + RegBits'(kz_pick))};
              misc_b = SrcZero;
            end
            step_d  = '0;
            state_d = StRcp;
          end
        end
      end

      // One divider op at a time; each starts when the divider is idle.
      StRcp: begin
        if (div_ready && !div_busy_q) begin
          div_valid = 1'b1;
          if (step_q < 5'd3) begin
            div_op = rpu_pkg::FpOpRcp;
            div_dst = RInv + step_q;
            div_a = {1'b0, SrcReg, RegBits'(RD + step_q)};
            div_b = SrcZero;
          end else if (step_q == 5'd3) begin
            div_op = rpu_pkg::FpOpDiv;
            div_dst = RSx;
            div_a = {1'b0, SrcReg, RegBits'(RD + RegBits'(kx))};
            div_b = {1'b0, SrcReg, RegBits'(RD + RegBits'(kz_q))};
          end else begin
            div_op = rpu_pkg::FpOpDiv;
            div_dst = RSy;
            div_a = {1'b0, SrcReg, RegBits'(RD + RegBits'(ky))};
            div_b = {1'b0, SrcReg, RegBits'(RD + RegBits'(kz_q))};
          end
          step_d = step_q + 5'd1;
          if (step_q == (Watertight ? 5'd4 : 5'd2)) begin
            step_d  = '0;
            state_d = StClipMul;
          end
        end
      end

      StClipMul: begin
        if (!div_busy_q) begin
          fma_valid = 1'b1;
          fma_op = rpu_pkg::FpOpMul;
          fma_dst = RBox + step_q;
          fma_a = {1'b0, SrcReg, RegBits'(RBox + step_q)};
          fma_b = {1'b0, SrcReg, RegBits'(RInv + (step_q < 5'd3 ? step_q : step_q - 5'd3))};
          step_d = step_q + 5'd1;
          if (step_q == 5'd5) begin
            step_d  = '0;
            axis_d  = '0;
            state_d = StClipEntry;
          end
        end
      end

      StClipEntry: begin
        if (fm_busy_q == '0) begin
          misc_valid = 1'b1;
          misc_op = rpu_pkg::FpOpGt;
          misc_kind = DstFlag;
          misc_dst = FEntry;
          misc_a = {1'b0, SrcReg, entry_reg};
          misc_b = {1'b0, SrcReg, RTNear};
          state_d = StClipExit;
        end
      end

      StClipExit: begin
        misc_valid = 1'b1;
        misc_op = rpu_pkg::FpOpLt;
        misc_kind = DstFlag;
        misc_dst = FExit;
        misc_a = {1'b0, SrcReg, exit_reg};
        misc_b = {1'b0, SrcReg, RTFar};
        state_d = StClipUpdate;
      end

      StClipUpdate: begin
        if (fm_busy_q == '0) begin
          near_we = flags_q[FEntry];
          far_we  = flags_q[FExit];
          axis_d  = axis_q + 2'd1;
          state_d = axis_q == 2'd2 ? StClipTest : StClipEntry;
        end
      end

      StClipTest: begin
        misc_valid = 1'b1;
        misc_op = rpu_pkg::FpOpLe;
        misc_kind = DstFlag;
        misc_dst = FNearFar;
        misc_a = {1'b0, SrcReg, RTNear};
        misc_b = {1'b0, SrcReg, RTFar};
        state_d = StClipEnd;
      end

      StClipEnd: begin
        if (fm_busy_q == '0) begin
          node_d  = '0;
          state_d = !flags_q[FNearFar] ? StRsp : HandOff ? StHandOff : StNodeReq;
        end
      end

      StNodeReq: begin
        mem_req_valid_o = 1'b1;
        mem_req_o.addr  = {node_addr[31:OffsetBits], OffsetBits'(0)};
        if (mem_req_ready_i) begin
          half_d  = node_addr[OffsetBits-1:2];
          nodes_d = nodes_q + 32'd1;
          state_d = StNodeWait;
        end
      end

      StNodeWait: begin
        mem_rsp_ready_o = 1'b1;
        if (mem_rsp_valid_i) begin
          // word0: kind in bits 1:0, above child or count above; word1: split or first.
          if (line_word[1:0] == 2'(rpu_pkg::KdNodeLeafKind)) begin
            count_d  = line_word[31:2];
            first_d  = next_word;
            k_d      = '0;
            leaves_d = leaves_q + 32'd1;
            state_d  = StLeafNext;
          end else begin
            axis_d  = line_word[1:0];
            above_d = line_word[31:2];
            split_d = next_word;
            step_d  = '0;
            state_d = StInner;
          end
        end
      end

      // §3 inner node: t_split = (s - O[a]) * inv[a], then its three compares.
      StInner: begin
        step_d = step_q + 5'd1;
        unique case (step_q)
          5'd0: begin
            misc_valid = 1'b1;
            misc_op = rpu_pkg::FpOpFromFp32;
            misc_kind = DstReg;
            misc_dst = RSplit;
            misc_a = {1'b0, SrcSplit, 5'd0};
            misc_b = SrcZero;
          end
          5'd1: begin
            if (fm_busy_q == '0) begin
              fma_valid = 1'b1;
              fma_op = rpu_pkg::FpOpSub;
              fma_dst = RTSplit;
              fma_a = {1'b0, SrcReg, RSplit};
              fma_b = {1'b0, SrcReg, RegBits'(RO + RegBits'(axis_q))};
              misc_valid = 1'b1;
              misc_op = rpu_pkg::FpOpLt;
              misc_kind = DstFlag;
              misc_dst = FOLt;
              misc_a = {1'b0, SrcReg, RegBits'(RO + RegBits'(axis_q))};
              misc_b = {1'b0, SrcReg, RSplit};
            end else begin
              step_d = step_q;
            end
          end
          5'd2: begin
            misc_valid = 1'b1;
            misc_op = rpu_pkg::FpOpEq;
            misc_kind = DstFlag;
            misc_dst = FOEq;
            misc_a = {1'b0, SrcReg, RegBits'(RO + RegBits'(axis_q))};
            misc_b = {1'b0, SrcReg, RSplit};
          end
          5'd3: begin
            if (fm_busy_q == '0) begin
              fma_valid = 1'b1;
              fma_op = rpu_pkg::FpOpMul;
              fma_dst = RTSplit;
              fma_a = {1'b0, SrcReg, RTSplit};
              fma_b = {1'b0, SrcReg, RegBits'(RInv + RegBits'(axis_q))};
            end else begin
              step_d = step_q;
            end
          end
          5'd4: begin
            if (fm_busy_q == '0) begin
              misc_valid = 1'b1;
              misc_op = rpu_pkg::FpOpLe;
              misc_kind = DstFlag;
              misc_dst = FSplitLeFar;
              misc_a = {1'b0, SrcReg, RTSplit};
              misc_b = {1'b0, SrcReg, RTFar};
            end else begin
              step_d = step_q;
            end
          end
          5'd5: begin
            misc_valid = 1'b1;
            misc_op = rpu_pkg::FpOpLe;
            misc_kind = DstFlag;
            misc_dst = FSplitLe0;
            misc_a = {1'b0, SrcReg, RTSplit};
            misc_b = SrcZero;
          end
          default: begin
            misc_valid = 1'b1;
            misc_op = rpu_pkg::FpOpLt;
            misc_kind = DstFlag;
            misc_dst = FSplitLtNear;
            misc_a = {1'b0, SrcReg, RTSplit};
            misc_b = {1'b0, SrcReg, RTNear};
            step_d  = '0;
            state_d = StInnerEnd;
          end
        endcase
      end

      StInnerEnd: begin
        if (fm_busy_q == '0) begin
          state_d = StNodeReq;
          if (!flags_q[FSplitLeFar] || flags_q[FSplitLe0]) begin
            node_d = first_child;   // the plane is behind, beyond, or (NaN) holds the ray
          end else if (flags_q[FSplitLtNear]) begin
            node_d = second_child;
          end else if (sp_q == SpBits'(StackDepth)) begin
            fault_d = 1'b1;
            state_d = StRsp;
          end else begin
            push   = 1'b1;
            sp_d   = sp_q + SpBits'(1);
            node_d = first_child;
            far_we = 1'b1;
          end
        end
      end

      // The list's end, or any-hit mode's first hit.
      StLeafNext: begin
        if (k_q == count_q || (hit_q && ray_q.any_hit)) begin
          state_d = StLeafEnd;
        end else begin
          mem_req_valid_o = 1'b1;
          mem_req_o.addr  = {ref_addr[31:OffsetBits], OffsetBits'(0)};
          if (mem_req_ready_i) begin
            half_d  = ref_addr[OffsetBits-1:2];
            state_d = StRefWait;
          end
        end
      end

      StRefWait: begin
        mem_rsp_ready_o = 1'b1;
        if (mem_rsp_valid_i) begin
          prim_d  = line_word;
          sent_d  = '0;
          got_d   = '0;
          state_d = StRecord;
        end
      end

      // The record's three lines, requested back to back, answered in order.
      StRecord: begin
        mem_req_valid_o = sent_q != SentBits'(RecordLines);
        mem_req_o.addr  = record_addr;
        if (mem_req_valid_o && mem_req_ready_i) sent_d = sent_q + SentBits'(1);
        mem_rsp_ready_o = 1'b1;
        if (mem_rsp_valid_i) begin
          record_we = 1'b1;
          got_d     = got_q + SentBits'(1);
          if (got_q == SentBits'(RecordLines - 1)) state_d = StIuReq;
        end
      end

      StIuReq: begin
        iu_req_valid_o = 1'b1;
        if (iu_req_ready_i) begin
          tests_d = tests_q + 32'd1;
          state_d = StIuWait;
        end
      end

      StIuWait: begin
        iu_rsp_ready_o = 1'b1;
        if (iu_rsp_valid_i) begin
          k_d     = k_q + IndexBits'(1);
          state_d = StLeafNext;
          if (iu_rsp_i.hit) begin
            best_we    = 1'b1;
            uv_we      = 1'b1;
            hit_d      = 1'b1;
            hit_prim_d = prim_q;
          end
        end
      end

      StLeafEnd: begin
        misc_valid = 1'b1;
        misc_op = rpu_pkg::FpOpLe;
        misc_kind = DstFlag;
        misc_dst = FBestLeFar;
        misc_a = {1'b0, SrcReg, RTBest};
        misc_b = {1'b0, SrcReg, RTFar};
        state_d = StLeafDecide;
      end

      StLeafDecide: begin
        if (fm_busy_q == '0) begin
          if ((hit_q && (ray_q.any_hit || flags_q[FBestLeFar])) || sp_q == '0) begin
            state_d = StFinish;
          end else begin
            // Pop: continue at the entry's node with its interval unless the hit is
            // nearer than the entry's near end (StPopDecide).
            node_d  = top[EntryBits-1 -: IndexBits];
            near_we = 1'b1;
            far_we  = 1'b1;
            sp_d = sp_q - SpBits'(1);
            state_d = StPop;
          end
        end
      end

      StPop: begin
        misc_valid = 1'b1;
        misc_op = rpu_pkg::FpOpLt;
        misc_kind = DstFlag;
        misc_dst = FBestLtNear;
        misc_a = {1'b0, SrcReg, RTBest};
        misc_b = {1'b0, SrcReg, RTNear};
        state_d = StPopDecide;
      end

      StPopDecide: begin
        if (fm_busy_q == '0) begin
          state_d = hit_q && flags_q[FBestLtNear] ? StFinish : StNodeReq;
        end
      end

      StFinish: begin
        misc_valid = 1'b1;
        misc_op    = rpu_pkg::FpOpToFp32;
        misc_kind  = DstOut;
        misc_dst   = step_q;
        step_d     = step_q + 5'd1;
        unique case (step_q)
          5'd0:    misc_a = {1'b0, SrcReg, RTBest};
          5'd1:    misc_a = {1'b0, SrcReg, RHitU};
          default: begin
            misc_a  = {1'b0, SrcReg, RHitV};
            step_d  = '0;
            state_d = StRsp;
          end
        endcase
      end

      StRsp: begin
        if (rsp_valid_o && rsp_ready_i) begin
          step_d  = '0;
          state_d = StIdle;
        end
      end

      StHandOff: begin
        if (start_ready_i) state_d = StIdle;
      end

      default: state_d = StIdle;
    endcase

    // Ops in flight: fma and misc answer after two cycles, the divider when it is done.
    fm_busy_d = fm_busy_q + 3'(fma_valid) + 3'(misc_valid) - 3'(fma_rsp_valid) - 3'(misc_rsp_valid);
    div_busy_d = div_valid || (div_busy_q && !div_rsp_valid);
  end

  // The values the state machine writes: the clip's interval (StValid, StClipUpdate), the
  // push's t_far = t_split, the popped entry's interval, an IU hit's t.
  assign near_wd = state_q == StClipUpdate ? rd(regs_q, entry_reg)
                 : state_q == StLeafDecide ? top[2*W-1:W]
                 : rd(regs_q, RTMin);
  assign far_wd  = state_q == StClipUpdate ? rd(regs_q, exit_reg)
                 : state_q == StInnerEnd   ? rd(regs_q, RTSplit)
                 : state_q == StLeafDecide ? top[W-1:0]
                 : rd(regs_q, RTMax);
  assign best_wd = state_q == StIuWait ? iu_rsp_i.t[W-1:0] : rd(regs_q, RTMax);

  // Register writes: a result goes to the register its tag names (misc's wins over the
  // divider's, the divider's over fma's); the state machine's writes win over results.
  logic misc_to_reg;
  assign misc_to_reg = misc_rsp_valid && misc_rsp.tag[7:6] != DstFlag && misc_rsp.tag[7:6] != DstOut;
  for (genvar i = 0; i < NumRegs; i++) begin : g_regs
    logic          fma_write, div_write, misc_write, sm_write;
    logic [W-1:0]  sm_value;
    assign fma_write  = fma_rsp_valid && fma_rsp.tag[4:0] == RegBits'(i);
    assign div_write  = div_rsp_valid && div_rsp.tag[4:0] == RegBits'(i);
    assign misc_write = misc_to_reg && misc_rsp.tag[4:0] == RegBits'(i);
    if (i == RTNear) begin : g_near
      assign sm_write = near_we;
      assign sm_value = near_wd;
    end else if (i == RTFar) begin : g_far
      assign sm_write = far_we;
      assign sm_value = far_wd;
    end else if (i == RTBest) begin : g_best
      assign sm_write = best_we;
      assign sm_value = best_wd;
    end else if (i == RHitU) begin : g_u
      assign sm_write = uv_we;
      assign sm_value = iu_rsp_i.u[W-1:0];
    end else if (i == RHitV) begin : g_v
      assign sm_write = uv_we;
      assign sm_value = iu_rsp_i.v[W-1:0];
    end else begin : g_none
      assign sm_write = 1'b0;
      assign sm_value = '0;
    end
    assign regs_d[i*W +: W] = sm_write   ? sm_value
                            : misc_write ? misc_rsp.result[W-1:0]
                            : div_write  ? div_rsp.result[W-1:0]
                            : fma_write  ? fma_rsp.result[W-1:0]
                            : regs_q[i*W +: W];
  end

  // Flags and the widened t, u, v: misc results tagged DstFlag and DstOut.
  for (genvar i = 0; i < NumFlags; i++) begin : g_flags
    assign flags_d[i] = misc_rsp_valid && misc_rsp.tag[7:6] == DstFlag && misc_rsp.tag[4:0] == 5'(i)
                        ? misc_rsp.result[0] : flags_q[i];
  end
  for (genvar i = 0; i < 3; i++) begin : g_out
    assign out_d[i*32 +: 32] = misc_rsp_valid && misc_rsp.tag[7:6] == DstOut && misc_rsp.tag[1:0] == 2'(i)
                               ? misc_rsp.result : out_q[i*32 +: 32];
  end

  // A push writes the entry at the stack pointer; the record's lines arrive in order.
  // (A HandOff engine never walks: no writes, so synthesis keeps neither.)
  for (genvar i = 0; i < StackDepth; i++) begin : g_stack
    assign stack_d[i*EntryBits +: EntryBits] = !HandOff && push && sp_q == SpBits'(i)
                                               ? {second_child, rd(regs_q, RTSplit), rd(regs_q, RTFar)}
                                               : stack_q[i*EntryBits +: EntryBits];
  end
  for (genvar i = 0; i < RecordLines; i++) begin : g_record
    assign record_d[i*LineBits +: LineBits] = !HandOff && record_we && got_q == SentBits'(i) ? mem_rsp_i.data
                                                                                : record_q[i*LineBits +: LineBits];
  end

  always_ff @(posedge clk_i or negedge rst_ni) begin : regs
    if (!rst_ni) begin
      state_q    <= StIdle;
      step_q     <= '0;
      ray_q      <= '0;
      regs_q     <= '0;
      flags_q    <= '0;
      out_q      <= '0;
      kz_q       <= 2'd2;
      axis_q     <= '0;
      node_q     <= '0;
      above_q    <= '0;
      count_q    <= '0;
      k_q        <= '0;
      split_q    <= '0;
      first_q    <= '0;
      prim_q     <= '0;
      hit_prim_q <= '0;
      hit_q      <= 1'b0;
      fault_q    <= 1'b0;
      half_q     <= '0;
      sent_q     <= '0;
      got_q      <= '0;
      record_q   <= '0;
      stack_q    <= '0;
      sp_q       <= '0;
      nodes_q    <= '0;
      leaves_q   <= '0;
      tests_q    <= '0;
      fm_busy_q  <= '0;
      div_busy_q <= 1'b0;
    end else begin
      state_q    <= state_d;
      step_q     <= step_d;
      ray_q      <= ray_d;
      regs_q     <= regs_d;
      flags_q    <= flags_d;
      out_q      <= out_d;
      kz_q       <= kz_d;
      axis_q     <= axis_d;
      node_q     <= node_d;
      above_q    <= above_d;
      count_q    <= count_d;
      k_q        <= k_d;
      split_q    <= split_d;
      first_q    <= first_d;
      prim_q     <= prim_d;
      hit_prim_q <= hit_prim_d;
      hit_q      <= hit_d;
      fault_q    <= fault_d;
      half_q     <= half_d;
      sent_q     <= sent_d;
      got_q      <= got_d;
      record_q   <= record_d;
      stack_q    <= stack_d;
      sp_q       <= sp_d;
      nodes_q    <= nodes_d;
      leaves_q   <= leaves_d;
      tests_q    <= tests_d;
      fm_busy_q  <= fm_busy_d;
      div_busy_q <= div_busy_d;
    end
  end

  // --- Outputs. ---
  assign iu_req_o.tag       = ray_q.tag;
  assign iu_req_o.origin    = {ext(rd(regs_q, RO + 2)), ext(rd(regs_q, RO + 1)), ext(rd(regs_q, RO))};
  assign iu_req_o.direction = {ext(rd(regs_q, RD + 2)), ext(rd(regs_q, RD + 1)), ext(rd(regs_q, RD))};
  assign iu_req_o.t_min     = ext(rd(regs_q, RTMin));
  assign iu_req_o.t_best    = ext(rd(regs_q, RTBest));
  assign iu_req_o.kx        = Watertight ? kx : 2'd0;
  assign iu_req_o.ky        = Watertight ? ky : 2'd1;
  assign iu_req_o.kz        = Watertight ? kz_q : 2'd2;
  assign iu_req_o.shear_x   = Watertight ? ext(rd(regs_q, RSx)) : '0;
  assign iu_req_o.shear_y   = Watertight ? ext(rd(regs_q, RSy)) : '0;
  assign iu_req_o.record    = record_q;

  assign start_ray_o     = iu_req_o;
  assign start_inv_o     = {ext(rd(regs_q, RInv + 2)), ext(rd(regs_q, RInv + 1)), ext(rd(regs_q, RInv))};
  assign start_t_near_o  = ext(rd(regs_q, RTNear));
  assign start_t_far_o   = ext(rd(regs_q, RTFar));
  assign start_any_hit_o = ray_q.any_hit;
  assign start_dir_le0_o = flags_q[FDLe0 +: 3];

  // A HandOff engine answers only rays that miss before the walk: no hit, no counts.
  assign rsp_o.tag    = ray_q.tag;
  assign rsp_o.hit    = !HandOff && hit_q;
  assign rsp_o.t      = world_t;
  assign rsp_o.u      = out_q[32 +: 32];
  assign rsp_o.v      = out_q[64 +: 32];
  assign rsp_o.prim   = HandOff ? '0 : hit_prim_q;
  assign rsp_o.nodes  = HandOff ? '0 : nodes_q;
  assign rsp_o.leaves = HandOff ? '0 : leaves_q;
  assign rsp_o.tests  = HandOff ? '0 : tests_q;
  assign rsp_o.fault  = !HandOff && fault_q;

  // Bits the unit does not read: the FP units' ready (they never stall here), result
  // bits above the format's width, tag bits beyond the destination, the IU's tag (one
  // test is in flight), the memory answer's tag (answers come in order) and the high
  // bits of its format values.
  logic unused;
  assign unused = ^{fma_ready_unused, misc_ready_unused, fma_rsp.tag[7:5], div_rsp.tag[7:5],
                    misc_rsp.tag[5], iu_rsp_i.tag, mem_rsp_i.tag, node_addr[2:0],
                    ref_addr[1:0]};
  if (W < 32) begin : g_unused_high
    logic unused_high;
    assign unused_high = ^{fma_rsp.result[31:W], div_rsp.result[31:W], iu_rsp_i.t[31:W],
                           iu_rsp_i.u[31:W], iu_rsp_i.v[31:W]};
  end

endmodule
