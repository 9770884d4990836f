// A pipelined divider: div(a, b), correctly rounded, one division accepted every cycle
// (rpu_fp_divsqrt's recurrence and rounding laid out in space instead of time: the
// same rpu_fp_divsqrt_load, rpu_fp_divsqrt_steps and rpu_fp_round, so both give the
// same bits). Stage 0 registers the decoded operands, stages 1..Cycles StepsPerStage
// quotient digits each, the last stage the rounded quotient: Cycles + 2 stages, with
// Cycles = Steps / StepsPerStage (Steps = FracBits + 3 rounded up to a multiple of
// StepsPerStage); fp32 with StepsPerStage = 2: 15 stages, as rpu_fp_divsqrt's latency.
//
// No handshake of its own: every stage moves when en_i is high (the enclosing pipeline
// stalls as a whole). side_i travels alongside the operands and leaves with their
// quotient, so the caller need not know the depth.
module rpu_fp_div_pipe #(
  parameter int unsigned ExpBits       = rpu_pkg::FormatFp32ExponentBits,
  parameter int unsigned FracBits      = rpu_pkg::FormatFp32FractionBits,
  parameter int unsigned StepsPerStage = 2,
  parameter int unsigned SideBits      = 1
) (
  input  logic                      clk_i,
  input  logic                      rst_ni,
  input  logic                      en_i,

  input  logic [ExpBits+FracBits:0] a_i,
  input  logic [ExpBits+FracBits:0] b_i,
  input  logic [SideBits-1:0]       side_i,

  output logic [ExpBits+FracBits:0] quotient_o,
  output logic [SideBits-1:0]       side_o
);

  localparam int unsigned Width    = 1 + ExpBits + FracBits;
  localparam int unsigned Steps    = (FracBits + 3 + StepsPerStage - 1) / StepsPerStage * StepsPerStage;
  localparam int unsigned Cycles   = Steps / StepsPerStage;
  localparam int unsigned RemBits  = Steps + 2;
  // Exponents here stay within +-(2^ExpBits + Steps), and rounding adds Steps + 1.
  localparam int unsigned ExpWidth = $clog2((2 << ExpBits) + 4 * Steps) + 1;
  // What every stage carries besides the recurrence: sign, exponent, the special case.
  localparam int unsigned CarryBits = SideBits + 1 + ExpWidth + 1 + Width + FracBits + 1;

  // Stage 0: the decoded operands.
  logic                       load_sign, load_special;
  logic signed [ExpWidth-1:0] load_exp;
  logic [RemBits-1:0]         load_rem;
  logic [2*Steps-1:0]         load_rad;
  logic [Width-1:0]           load_special_value;
  logic [FracBits:0]          load_divisor;

  rpu_fp_divsqrt_load #(.ExpBits(ExpBits), .FracBits(FracBits), .Steps(Steps), .ExpWidth(ExpWidth)) u_load (
    .sqrt_i(1'b0), .a_i, .b_i, .sign_o(load_sign), .exp_o(load_exp), .rem_o(load_rem), .rad_o(load_rad),
    .divisor_o(load_divisor), .special_o(load_special), .special_value_o(load_special_value)
  );

  // Stage s's registers: {rem, root, carry} in bits [s*StageBits +: StageBits].
  localparam int unsigned StageBits = RemBits + Steps + CarryBits;
  logic [(Cycles+1)*StageBits-1:0] stage_q;

  rpu_en_reg #(.Width(StageBits)) u_stage0 (
    .clk_i, .rst_ni, .en_i,
    .data_i({load_rem, Steps'(0), side_i, load_sign, load_exp, load_special, load_special_value, load_divisor}),
    .data_o(stage_q[0 +: StageBits])
  );

  for (genvar s = 1; s <= Cycles; s++) begin : g_stage
    logic [RemBits-1:0]   rem_in, rem;
    logic [Steps-1:0]     root_in, root;
    logic [CarryBits-1:0] carry;
    logic [2*Steps-1:0]   rad_unused;  // square roots only

    assign {rem_in, root_in, carry} = stage_q[(s-1)*StageBits +: StageBits];

    rpu_fp_divsqrt_steps #(.FracBits(FracBits), .Steps(Steps), .Count(StepsPerStage)) u_steps (
      .sqrt_i(1'b0), .rem_i(rem_in), .root_i(root_in), .rad_i('0), .divisor_i(carry[FracBits:0]),
      .rem_o(rem), .root_o(root), .rad_o(rad_unused)
    );

    rpu_en_reg #(.Width(StageBits)) u_stage (
      .clk_i, .rst_ni, .en_i, .data_i({rem, root, carry}), .data_o(stage_q[s*StageBits +: StageBits])
    );

    logic unused;
    assign unused = ^rad_unused;
  end

  // The last stage: rounding.
  logic [SideBits-1:0]        side;
  logic                       sign, special;
  logic signed [ExpWidth-1:0] exp;
  logic [Width-1:0]           special_value, rounded;
  logic [FracBits:0]          divisor_unused;
  logic [RemBits-1:0]         rem;
  logic [Steps-1:0]           root;
  assign {rem, root, side, sign, exp, special, special_value, divisor_unused} = stage_q[Cycles*StageBits +: StageBits];

  rpu_fp_round #(
    .ExpBits(ExpBits), .FracBits(FracBits), .SigBits(Steps + 1), .ExpWidth(ExpWidth)
  ) u_round (
    .sign_i(sign), .exp_i(exp), .sig_i({root, |rem}), .result_o(rounded)
  );

  rpu_en_reg #(.Width(Width + SideBits)) u_result (
    .clk_i, .rst_ni, .en_i, .data_i({special ? special_value : rounded, side}), .data_o({quotient_o, side_o})
  );

  // A division's radicand is zero; the divisor is done with after the last step.
  logic unused;
  assign unused = ^{load_rad, divisor_unused};

endmodule
