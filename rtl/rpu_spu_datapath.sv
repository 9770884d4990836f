// The shader core's vector datapath (docs/chip.md "Shader core"): one thread's
// instruction a cycle, four lanes wide, every result Latency cycles after its operands
// (the fixed-latency part of the core; rcp, rsq and sqrt go to rpu_spu_sfu instead).
// Every rounded operation runs on the FP units (docs/rtl.md), so no arithmetic is
// written twice:
//   - source lanes are fp32 bits rounded into the format by rpu_fp_misc_core's
//     from_fp32 (twelve, one per source lane), then abs and neg (soft.hpp: a NaN stays
//     as it is);
//   - add, mul, mad, frc on four rpu_fp_fma; min, max, flr, the compares, i2f and f2i on
//     four rpu_fp_misc;
//   - dp3 and dp4 as the functional model orders them: the products on the four fma
//     units, then (x + y) and (z + w) on two more, then the last sum on a seventh:
//     three fma latencies, which set Latency;
//   - results leave through rpu_fp_misc_core's to_fp32 (exact widening).
// Integer, move, select and the raw values the core hands in (rdsr, mfra, a load's
// or a ray's result) take the same Latency, so results come out in issue order and the
// register file needs one write port.
module rpu_spu_datapath #(
  parameter int unsigned ExpBits  = rpu_pkg::FormatFp32ExponentBits,
  parameter int unsigned FracBits = rpu_pkg::FormatFp32FractionBits,
  parameter int unsigned CtrlBits = 1,
  // rpu_fp_fma's latency (docs/rtl.md); a sum of a dot product is three of them deep.
  localparam int unsigned FmaLatency = 2,
  localparam int unsigned Latency = 3 * FmaLatency
) (
  input  logic                clk_i,
  input  logic                rst_ni,

  input  logic                valid_i,
  input  logic [rpu_pkg::IsaOpcodeWidth-1:0] op_i,  // rpu_pkg::opcode_e's values
  // A value handed in (a_i) instead of an instruction: written as it is, rounded into
  // the format first (a float load), or widened (a format value from the sfu).
  input  logic                hand_i,
  input  logic                hand_round_i,
  input  logic                hand_widen_i,
  input  logic [127:0]        a_i,          // swizzled source lanes (or the value handed in)
  input  logic [127:0]        b_i,
  input  logic [127:0]        c_i,
  input  logic [2:0]          neg_i,        // per source a, b, c
  input  logic [2:0]          abs_i,
  input  logic [31:0]         imm_i,
  input  logic [127:0]        raw_i,        // rdsr's or mfra's value
  input  logic [CtrlBits-1:0] ctrl_i,       // travels with the op

  output logic                valid_o,
  output logic [127:0]        result_o,
  output logic [CtrlBits-1:0] ctrl_o,
  // Source a in the format after abs and neg, at E: the sfu's operand.
  output logic [127:0]        src_a_fmt_o
);

  localparam int unsigned Width = 1 + ExpBits + FracBits;
  localparam int unsigned OpBits = rpu_pkg::FpOperandBits;

  // How the result is formed at the end of the pipeline (bits, not an enum: the delay
  // lines hold them as vectors and Yosys 0.23 reads no enum casts).
  localparam int unsigned ResBits = 3;
  localparam logic [ResBits-1:0]
    ResRaw      = 3'd0,  // the integer, move or handed-in lanes as they are
    ResWidenRaw = 3'd1,  // the raw lanes hold format values: widen them (lif, float loads, sfu)
    ResFma      = 3'd2,  // widen the fma units' lanes
    ResMisc     = 3'd3,  // widen the misc units' lanes
    ResMiscMask = 3'd4,  // a compare's 0/1 as 0 or 0xffffffff
    ResMiscRaw  = 3'd5,  // f2i's integer
    ResDot      = 3'd6;  // widen the dot product, in every lane

  // ---------------------------------------------------------------------------------
  // Source lanes in the format.
  // ---------------------------------------------------------------------------------
  function automatic logic [OpBits-1:0] sign_mods(input logic [OpBits-1:0] v, input logic neg, input logic abs);
    // v is a format value right-aligned in 32 bits: a NaN keeps its sign (soft.hpp).
    logic nan;
    nan = &v[Width-2:FracBits] && |v[FracBits-1:0];
    sign_mods = v;
    if (!nan && abs) sign_mods[Width-1] = 1'b0;
    if (!nan && neg) sign_mods[Width-1] = ~sign_mods[Width-1];
  endfunction

  logic [3*128-1:0] src_raw, src_fmt;
  assign src_raw = {c_i, b_i, (op_i == rpu_pkg::OpLif && !hand_i) ? {4{imm_i}} : a_i};

  for (genvar s = 0; s < 3; s++) begin : g_src
    for (genvar l = 0; l < 4; l++) begin : g_lane
      logic [OpBits-1:0] rounded;
      rpu_fp_misc_core #(.ExpBits(ExpBits), .FracBits(FracBits)) u_from_fp32 (
        .op_i(rpu_pkg::FpOpFromFp32), .a_i(src_raw[s*128+l*32 +: 32]), .b_i('0), .result_o(rounded)
      );
      // A widened handed-in value is a format value already.
      assign src_fmt[s*128+l*32 +: 32] = (s == 0 && hand_i && hand_widen_i) ? src_raw[l*32 +: 32]
                                          : sign_mods(rounded, neg_i[s], abs_i[s]);
    end
  end

  logic [127:0] fa, fb, fc;
  assign {fc, fb, fa} = src_fmt;
  assign src_a_fmt_o = fa;

  // ---------------------------------------------------------------------------------
  // Decode: which unit, which op, which result.
  // ---------------------------------------------------------------------------------
  logic                use_fma, use_misc, dot, dp3;
  rpu_pkg::fp_op_e     fma_op, misc_op;
  logic [ResBits-1:0]  res;
  logic                misc_raw_a;  // i2f reads the integer bits, not a format value

  always_comb begin : decode_op
    use_fma    = 1'b0;
    use_misc   = 1'b0;
    dot        = 1'b0;
    dp3        = 1'b0;
    fma_op     = rpu_pkg::FpOpAdd;
    misc_op    = rpu_pkg::FpOpMin;
    misc_raw_a = 1'b0;
    res        = ResRaw;
    if (hand_i) begin
      res = hand_round_i || hand_widen_i ? ResWidenRaw : ResRaw;
    end else begin
      unique case (op_i)
        rpu_pkg::OpAdd, rpu_pkg::OpMul, rpu_pkg::OpMad, rpu_pkg::OpFrc: begin
          use_fma = 1'b1;
          res     = ResFma;
          fma_op  = op_i == rpu_pkg::OpAdd ? rpu_pkg::FpOpAdd
                  : op_i == rpu_pkg::OpMul ? rpu_pkg::FpOpMul
                  : op_i == rpu_pkg::OpMad ? rpu_pkg::FpOpFma : rpu_pkg::FpOpFract;
        end
        rpu_pkg::OpDp3, rpu_pkg::OpDp4: begin
          use_fma = 1'b1;
          dot     = 1'b1;
          dp3     = op_i == rpu_pkg::OpDp3;
          fma_op  = rpu_pkg::FpOpMul;
          res     = ResDot;
        end
        rpu_pkg::OpMin, rpu_pkg::OpMax, rpu_pkg::OpFlr: begin
          use_misc = 1'b1;
          res      = ResMisc;
          misc_op  = op_i == rpu_pkg::OpMin ? rpu_pkg::FpOpMin
                   : op_i == rpu_pkg::OpMax ? rpu_pkg::FpOpMax : rpu_pkg::FpOpFloor;
        end
        rpu_pkg::OpFeq, rpu_pkg::OpFne, rpu_pkg::OpFlt, rpu_pkg::OpFle: begin
          use_misc = 1'b1;
          res      = ResMiscMask;
          misc_op  = op_i == rpu_pkg::OpFeq ? rpu_pkg::FpOpEq
                   : op_i == rpu_pkg::OpFne ? rpu_pkg::FpOpNe
                   : op_i == rpu_pkg::OpFlt ? rpu_pkg::FpOpLt : rpu_pkg::FpOpLe;
        end
        rpu_pkg::OpI2f: begin
          use_misc   = 1'b1;
          res        = ResMisc;
          misc_op    = rpu_pkg::FpOpFromInt32;
          misc_raw_a = 1'b1;
        end
        rpu_pkg::OpF2i: begin
          use_misc = 1'b1;
          res      = ResMiscRaw;
          misc_op  = rpu_pkg::FpOpToInt32;
        end
        rpu_pkg::OpLif: res = ResWidenRaw;
        default: res = ResRaw;
      endcase
    end
  end

  // ---------------------------------------------------------------------------------
  // Integer, move and select lanes (combinational), and the format lanes that are only
  // widened (lif, handed-in values): both ride the raw delay line.
  // ---------------------------------------------------------------------------------
  function automatic logic [31:0] fp32_sign_mods(input logic [31:0] v, input logic neg, input logic abs);
    // mov's modifiers act on the raw lane as fp32 bits (spec/isa.toml).
    logic nan;
    nan = &v[30:23] && |v[22:0];
    fp32_sign_mods = v;
    if (!nan && abs) fp32_sign_mods[31] = 1'b0;
    if (!nan && neg) fp32_sign_mods[31] = ~fp32_sign_mods[31];
  endfunction

  logic [127:0] int_lanes;
  for (genvar l = 0; l < 4; l++) begin : g_int
    logic [31:0] a, b, c, r;
    logic [63:0] product;
    assign a = a_i[l*32 +: 32];
    assign b = b_i[l*32 +: 32];
    assign c = c_i[l*32 +: 32];
    assign product = {32'd0, a} * {32'd0, op_i == rpu_pkg::OpImuli ? imm_i : b};
    always_comb begin : int_op
      unique case (op_i)
        rpu_pkg::OpMov:    r = fp32_sign_mods(a, neg_i[0], abs_i[0]);
        rpu_pkg::OpSel:    r = a != '0 ? b : c;
        rpu_pkg::OpIadd:   r = a + b;
        rpu_pkg::OpIsub:   r = a - b;
        rpu_pkg::OpImul:   r = product[31:0];
        rpu_pkg::OpImulhu: r = product[63:32];
        rpu_pkg::OpAnd:    r = a & b;
        rpu_pkg::OpOr:     r = a | b;
        rpu_pkg::OpXor:    r = a ^ b;
        rpu_pkg::OpShl:    r = a << b[4:0];
        rpu_pkg::OpShr:    r = a >> b[4:0];
        rpu_pkg::OpSra:    r = $signed(a) >>> b[4:0];
        rpu_pkg::OpIeq:    r = a == b ? '1 : '0;
        rpu_pkg::OpIlt:    r = $signed(a) < $signed(b) ? '1 : '0;
        rpu_pkg::OpIltu:   r = a < b ? '1 : '0;
        rpu_pkg::OpIaddi:  r = a + imm_i;
        rpu_pkg::OpImuli:  r = product[31:0];
        rpu_pkg::OpAndi:   r = a & imm_i;
        rpu_pkg::OpOri:    r = a | imm_i;
        rpu_pkg::OpXori:   r = a ^ imm_i;
        rpu_pkg::OpShli:   r = a << imm_i[4:0];
        rpu_pkg::OpShri:   r = a >> imm_i[4:0];
        rpu_pkg::OpSrai:   r = $signed(a) >>> imm_i[4:0];
        rpu_pkg::OpIlti:   r = $signed(a) < $signed(imm_i) ? '1 : '0;
        rpu_pkg::OpLi:     r = imm_i;
        default:           r = raw_i[l*32 +: 32];
      endcase
    end
    assign int_lanes[l*32 +: 32] = r;
  end

  logic [127:0] raw_e;
  always_comb begin : pick_raw
    if (hand_i && !hand_round_i && !hand_widen_i) raw_e = a_i;
    else if (res == ResWidenRaw) raw_e = fa;
    else raw_e = int_lanes;
  end

  // ---------------------------------------------------------------------------------
  // The FP units: four fma and four misc, fixed latency (never stalled).
  // ---------------------------------------------------------------------------------
  logic [127:0] fma_out, misc_out;
  logic [3:0]   fma_ready, misc_ready, fma_valid, misc_valid;
  logic [4*rpu_pkg::FpTagBits-1:0] unused_tags;

  for (genvar l = 0; l < 4; l++) begin : g_unit
    // Requests {op, tag, a, b, c} and responses {tag, result} as vectors: Yosys 0.23
    // resolves no struct fields of signals declared in a generate block.
    logic [rpu_pkg::FpReqBits-1:0] fma_req, misc_req;
    logic [rpu_pkg::FpRspBits-1:0] fma_rsp, misc_rsp;
    assign fma_req  = {fma_op, rpu_pkg::FpTagBits'(0), fa[l*32 +: 32], fb[l*32 +: 32], fc[l*32 +: 32]};
    assign misc_req = {misc_op, rpu_pkg::FpTagBits'(0), misc_raw_a ? a_i[l*32 +: 32] : fa[l*32 +: 32],
                       fb[l*32 +: 32], 32'd0};
    rpu_fp_fma #(.ExpBits(ExpBits), .FracBits(FracBits)) u_fma (
      .clk_i, .rst_ni,
      .req_valid_i(valid_i && use_fma), .req_ready_o(fma_ready[l]), .req_i(fma_req),
      .rsp_valid_o(fma_valid[l]), .rsp_ready_i(1'b1), .rsp_o(fma_rsp)
    );
    rpu_fp_misc #(.ExpBits(ExpBits), .FracBits(FracBits)) u_misc (
      .clk_i, .rst_ni,
      .req_valid_i(valid_i && use_misc), .req_ready_o(misc_ready[l]), .req_i(misc_req),
      .rsp_valid_o(misc_valid[l]), .rsp_ready_i(1'b1), .rsp_o(misc_rsp)
    );
    assign fma_out[l*32 +: 32]  = fma_rsp[OpBits-1:0];
    assign misc_out[l*32 +: 32] = misc_rsp[OpBits-1:0];
    assign unused_tags[l*rpu_pkg::FpTagBits +: rpu_pkg::FpTagBits] = fma_rsp[OpBits +: rpu_pkg::FpTagBits]
                                                                    ^ misc_rsp[OpBits +: rpu_pkg::FpTagBits];
  end

  // Dot products: (x + y) and (z + w) FmaLatency after the products, then the last sum.
  // Delay lines are flat vectors (Yosys 0.23 mis-reads arrays of packed types): entry k
  // holds what entered k + 1 cycles ago.
  logic [Latency-1:0]   dot_q, dp3_q;        // a dot product, dp3
  logic [127:0]         dot_out;
  rpu_pkg::fp_req_t     sum01_req, sum23_req, sum_req;
  rpu_pkg::fp_rsp_t     sum01_rsp, sum23_rsp, sum_rsp;
  logic [2:0]           sum_ready, sum_valid;
  logic [FmaLatency*OpBits-1:0] p2_q;        // z's product, for dp3's last sum
  logic                 dot_a, dp3_a;        // at the products' output (E + FmaLatency)
  logic                 dot_b, dp3_b;        // at the pair sums' output (E + 2 FmaLatency)

  assign sum01_req = {rpu_pkg::FpOpAdd, rpu_pkg::FpTagBits'(0), fma_out[0 +: 32], fma_out[32 +: 32], 32'd0};
  assign sum23_req = {rpu_pkg::FpOpAdd, rpu_pkg::FpTagBits'(0), fma_out[64 +: 32], fma_out[96 +: 32], 32'd0};
  assign sum_req   = {rpu_pkg::FpOpAdd, rpu_pkg::FpTagBits'(0), sum01_rsp.result,
                      dp3_b ? p2_q[OpBits*(FmaLatency-1) +: OpBits] : sum23_rsp.result, 32'd0};
  assign dot_a = dot_q[FmaLatency-1];
  assign dp3_a = dp3_q[FmaLatency-1];
  assign dot_b = dot_q[2*FmaLatency-1];
  assign dp3_b = dp3_q[2*FmaLatency-1];

  rpu_fp_fma #(.ExpBits(ExpBits), .FracBits(FracBits)) u_sum01 (
    .clk_i, .rst_ni,
    .req_valid_i(fma_valid[0] && dot_a), .req_ready_o(sum_ready[0]), .req_i(sum01_req),
    .rsp_valid_o(sum_valid[0]), .rsp_ready_i(1'b1), .rsp_o(sum01_rsp)
  );
  rpu_fp_fma #(.ExpBits(ExpBits), .FracBits(FracBits)) u_sum23 (
    .clk_i, .rst_ni,
    .req_valid_i(fma_valid[2] && dot_a && !dp3_a), .req_ready_o(sum_ready[1]), .req_i(sum23_req),
    .rsp_valid_o(sum_valid[1]), .rsp_ready_i(1'b1), .rsp_o(sum23_rsp)
  );
  rpu_fp_fma #(.ExpBits(ExpBits), .FracBits(FracBits)) u_sum (
    .clk_i, .rst_ni,
    .req_valid_i(sum_valid[0] && dot_b), .req_ready_o(sum_ready[2]), .req_i(sum_req),
    .rsp_valid_o(sum_valid[2]), .rsp_ready_i(1'b1), .rsp_o(sum_rsp)
  );
  assign dot_out = {4{sum_rsp.result}};

  // ---------------------------------------------------------------------------------
  // Delay lines to the common latency. Entry k holds what entered k + 1 cycles ago.
  // ---------------------------------------------------------------------------------
  logic [Latency-1:0]            valid_d, valid_q, dot_d, dp3_d;
  logic [Latency*ResBits-1:0]    res_d, res_q;
  logic [Latency*128-1:0]        raw_d, raw_q;
  logic [Latency*CtrlBits-1:0]   ctrl_d, ctrl_q;
  logic [FmaLatency*OpBits-1:0]  p2_d;
  logic [(Latency-FmaLatency)*128-1:0] unit_d, unit_q;  // fma or misc lanes from E + FmaLatency on
  logic [ResBits-1:0]            res_at_units;            // the op at the units' outputs

  assign res_at_units = res_q[ResBits*(FmaLatency-1) +: ResBits];
  assign valid_d = {valid_q[Latency-2:0], valid_i};
  assign dot_d   = {dot_q[Latency-2:0], valid_i && dot};
  assign dp3_d   = {dp3_q[Latency-2:0], dp3};
  assign res_d   = {res_q[ResBits*(Latency-1)-1:0], res};
  assign raw_d   = {raw_q[128*(Latency-1)-1:0], raw_e};
  assign ctrl_d  = {ctrl_q[CtrlBits*(Latency-1)-1:0], ctrl_i};
  assign p2_d    = {p2_q[OpBits*(FmaLatency-1)-1:0], fma_out[64 +: 32]};
  assign unit_d  = {unit_q[128*(Latency-FmaLatency-1)-1:0], res_at_units == ResFma ? fma_out : misc_out};

  always_ff @(posedge clk_i or negedge rst_ni) begin : delay_lines
    if (!rst_ni) begin
      valid_q <= '0;
      dot_q   <= '0;
      dp3_q   <= '0;
      res_q   <= '0;
      raw_q   <= '0;
      ctrl_q  <= '0;
      p2_q    <= '0;
      unit_q  <= '0;
    end else begin
      valid_q <= valid_d;
      dot_q   <= dot_d;
      dp3_q   <= dp3_d;
      res_q   <= res_d;
      raw_q   <= raw_d;
      ctrl_q  <= ctrl_d;
      p2_q    <= p2_d;
      unit_q  <= unit_d;
    end
  end

  // ---------------------------------------------------------------------------------
  // The end: widen format values to fp32.
  // ---------------------------------------------------------------------------------
  logic [ResBits-1:0] res_w;
  logic [127:0] raw_w, unit_w, fmt_w;
  assign res_w  = res_q[ResBits*(Latency-1) +: ResBits];
  assign raw_w  = raw_q[128*(Latency-1) +: 128];
  assign unit_w = unit_q[128*(Latency-FmaLatency-1) +: 128];
  assign fmt_w  = res_w == ResDot ? dot_out : res_w == ResWidenRaw ? raw_w : unit_w;

  for (genvar l = 0; l < 4; l++) begin : g_widen
    logic [OpBits-1:0] wide;
    rpu_fp_misc_core #(.ExpBits(ExpBits), .FracBits(FracBits)) u_to_fp32 (
      .op_i(rpu_pkg::FpOpToFp32), .a_i(fmt_w[l*32 +: 32]), .b_i('0), .result_o(wide)
    );
    always_comb begin : pick_lane_result
      unique case (res_w)
        ResRaw:      result_o[l*32 +: 32] = raw_w[l*32 +: 32];
        ResMiscMask: result_o[l*32 +: 32] = unit_w[l*32] ? '1 : '0;
        ResMiscRaw:  result_o[l*32 +: 32] = unit_w[l*32 +: 32];
        default:     result_o[l*32 +: 32] = wide;
      endcase
    end
  end

  assign valid_o = valid_q[Latency-1];
  assign ctrl_o  = ctrl_q[CtrlBits*(Latency-1) +: CtrlBits];

  logic unused;
  assign unused = ^{unused_tags, fma_ready, misc_ready, sum_ready, sum_valid[1], misc_valid[3:1],
                    fma_valid[3], fma_valid[1], sum23_rsp.tag, sum01_rsp.tag, sum_rsp.tag};

`ifndef SYNTHESIS
  // The units are pipelines that never stall here: a request is always taken and its
  // result comes FmaLatency later, when the delay lines expect it.
  always_ff @(posedge clk_i or negedge rst_ni) begin : check_unit_timing
    if (rst_ni) begin
      assert (&fma_ready && &misc_ready && &sum_ready) else $error("rpu_spu_datapath: an FP unit stalled");
      assert (fma_valid[0] == (valid_q[FmaLatency-1] && (res_at_units == ResFma || res_at_units == ResDot)))
        else $error("rpu_spu_datapath: an fma result off its cycle");
      assert (misc_valid[0] == (valid_q[FmaLatency-1]
                                && (res_at_units == ResMisc || res_at_units == ResMiscMask || res_at_units == ResMiscRaw)))
        else $error("rpu_spu_datapath: a misc result off its cycle");
      assert (sum_valid[2] == (valid_q[Latency-1] && res_w == ResDot))
        else $error("rpu_spu_datapath: a dot product off its cycle");
    end
  end
`endif

endmodule
