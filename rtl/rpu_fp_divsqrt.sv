// The division and square-root unit: div, rcp, sqrt, rsqrt (spec/fp_units.toml),
// correctly rounded by digit recurrence (restoring, radix 2, StepsPerCycle digits a
// cycle; Ercegovac & Lang, "Digital Arithmetic", ch. 5 and 6):
//   div(a, b)  quotient digits of sig_a / sig_b, the remainder as the sticky bit
//   rcp(a)     div(1, a)
//   sqrt(a)    root digits of the significand (scaled to an even exponent), the
//              remainder as the sticky bit
//   rsqrt(a)   rcp(sqrt(a)): a second pass on the rounded root, two roundings as
//              soft::rsqrt defines it
// Both recurrences produce Steps >= FracBits+3 digits, so the rounded significand has
// a guard bit above the sticky bit (rpu_fp_round).
//
// Iterative, one operation at a time: with Cycles = Steps / StepsPerCycle
// (Steps = FracBits + 3 rounded up to a multiple of StepsPerCycle), the latency from
// req_valid_i && req_ready_o to rsp_valid_o is Cycles + 2 for div, rcp and sqrt and
// 2 * Cycles + 3 for rsqrt; req_ready_o is high only when the unit is idle, so the
// initiation interval is the latency plus one. fp32 with StepsPerCycle = 2: latency
// 15 (rsqrt 29), interval 16 (30).
module rpu_fp_divsqrt #(
  parameter int unsigned ExpBits       = rpu_pkg::FormatFp32ExponentBits,
  parameter int unsigned FracBits      = rpu_pkg::FormatFp32FractionBits,
  parameter int unsigned StepsPerCycle = 2
) (
  input  logic             clk_i,
  input  logic             rst_ni,

  input  logic             req_valid_i,
  output logic             req_ready_o,
  input  rpu_pkg::fp_req_t req_i,

  output logic             rsp_valid_o,
  input  logic             rsp_ready_i,
  output rpu_pkg::fp_rsp_t rsp_o
);

  localparam int unsigned Width     = 1 + ExpBits + FracBits;
  localparam int unsigned Steps     = (FracBits + 3 + StepsPerCycle - 1) / StepsPerCycle * StepsPerCycle;
  localparam int unsigned Cycles    = Steps / StepsPerCycle;
  localparam int unsigned RemBits   = Steps + 2;
  localparam int unsigned RadBits   = 2 * Steps;
  localparam int unsigned CountBits = $clog2(Cycles + 1);
  // Exponents here stay within +-(2^ExpBits + Steps), and rounding adds Steps + 1.
  localparam int unsigned ExpWidth  = $clog2((2 << ExpBits) + 4 * Steps) + 1;
  localparam logic [Width-1:0] One = {2'b00, {(ExpBits - 1){1'b1}}, {FracBits{1'b0}}};

  typedef enum logic [1:0] {
    StIdle,  // waiting for a request
    StBusy,  // iterating; when count_q is 0, rounding (and maybe starting rsqrt's rcp)
    StDone   // holding the response
  } state_e;

  state_e                        state_d, state_q;
  logic [CountBits-1:0]          count_d, count_q;
  logic                          sqrt_d, sqrt_q;             // this pass is a square root
  logic                          rcp_next_d, rcp_next_q;     // rsqrt: an rcp pass follows
  logic [RemBits-1:0]            rem_d, rem_q;
  logic [Steps-1:0]              root_d, root_q;             // quotient or root digits
  logic [RadBits-1:0]            rad_d, rad_q;               // radicand digits still to use
  logic [FracBits:0]             divisor_d, divisor_q;
  logic                          sign_d, sign_q;
  logic signed [ExpWidth-1:0]    exp_d, exp_q;               // exponent of {root, sticky} bit 0
  logic                          special_d, special_q;       // result is special_value_q
  logic [Width-1:0]              special_value_d, special_value_q;
  logic [rpu_pkg::FpTagBits-1:0] tag_d, tag_q;
  logic [Width-1:0]              result_d, result_q;

  // Start of a pass: decode the operands, find the special results and set up the
  // recurrence. The operands come from a request, or from the rounded root for
  // rsqrt's second pass.
  logic                       load_sqrt;
  logic [Width-1:0]           load_a, load_b;
  logic                       load_sign, load_special;
  logic [Width-1:0]           load_special_value;
  logic signed [ExpWidth-1:0] load_exp;
  logic [RemBits-1:0]         load_rem;
  logic [RadBits-1:0]         load_rad;
  logic [FracBits:0]          load_divisor;

  rpu_fp_divsqrt_load #(.ExpBits(ExpBits), .FracBits(FracBits), .Steps(Steps), .ExpWidth(ExpWidth)) u_load (
    .sqrt_i(load_sqrt), .a_i(load_a), .b_i(load_b), .sign_o(load_sign), .exp_o(load_exp),
    .rem_o(load_rem), .rad_o(load_rad), .divisor_o(load_divisor), .special_o(load_special),
    .special_value_o(load_special_value)
  );

  logic [RemBits-1:0] step_rem;
  logic [Steps-1:0]   step_root;
  logic [RadBits-1:0] step_rad;

  rpu_fp_divsqrt_steps #(.FracBits(FracBits), .Steps(Steps), .Count(StepsPerCycle)) u_steps (
    .sqrt_i(sqrt_q), .rem_i(rem_q), .root_i(root_q), .rad_i(rad_q), .divisor_i(divisor_q),
    .rem_o(step_rem), .root_o(step_root), .rad_o(step_rad)
  );

  logic [Width-1:0] rounded, pass_result;
  rpu_fp_round #(
    .ExpBits(ExpBits), .FracBits(FracBits), .SigBits(Steps + 1), .ExpWidth(ExpWidth)
  ) u_round (
    .sign_i(sign_q), .exp_i(exp_q), .sig_i({root_q, |rem_q}), .result_o(rounded)
  );
  assign pass_result = special_q ? special_value_q : rounded;

  logic accept;
  assign req_ready_o = state_q == StIdle;
  assign accept      = req_valid_i && req_ready_o;

  // Which pass starts this cycle, and on which operands: a request, or the rcp of
  // rsqrt's rounded root once its square-root pass is done.
  logic load;
  always_comb begin : start_pass
    load      = 1'b0;
    load_sqrt = 1'b0;
    load_a    = req_i.a[Width-1:0];
    load_b    = req_i.b[Width-1:0];
    if (accept) begin
      load      = 1'b1;
      load_sqrt = req_i.op == rpu_pkg::FpOpSqrt || req_i.op == rpu_pkg::FpOpRsqrt;
      if (req_i.op == rpu_pkg::FpOpRcp) begin
        load_a = One;
        load_b = req_i.a[Width-1:0];
      end
    end else if (state_q == StBusy && count_q == '0 && rcp_next_q) begin
      load   = 1'b1;
      load_a = One;
      load_b = pass_result;
    end
  end

  always_comb begin : next_state
    state_d         = state_q;
    count_d         = count_q;
    sqrt_d          = sqrt_q;
    rcp_next_d      = rcp_next_q;
    rem_d           = rem_q;
    root_d          = root_q;
    rad_d           = rad_q;
    divisor_d       = divisor_q;
    sign_d          = sign_q;
    exp_d           = exp_q;
    special_d       = special_q;
    special_value_d = special_value_q;
    tag_d           = tag_q;
    result_d        = result_q;

    unique case (state_q)
      StIdle: begin
        if (accept) begin
          rcp_next_d = req_i.op == rpu_pkg::FpOpRsqrt;
          tag_d      = req_i.tag;
          state_d    = StBusy;
        end
      end
      StBusy: begin
        if (count_q != '0) begin
          count_d = count_q - CountBits'(1);
          rem_d   = step_rem;
          root_d  = step_root;
          rad_d   = step_rad;
        end else if (rcp_next_q) begin
          rcp_next_d = 1'b0;  // the rcp pass starts through `load`
        end else begin
          result_d = pass_result;
          state_d  = StDone;
        end
      end
      StDone: begin
        if (rsp_ready_i) state_d = StIdle;
      end
      default: state_d = StIdle;
    endcase

    if (load) begin
      count_d         = CountBits'(Cycles);
      sqrt_d          = load_sqrt;
      rem_d           = load_rem;
      root_d          = '0;
      rad_d           = load_rad;
      divisor_d       = load_divisor;
      sign_d          = load_sign;
      exp_d           = load_exp;
      special_d       = load_special;
      special_value_d = load_special_value;
    end
  end

  always_ff @(posedge clk_i or negedge rst_ni) begin : regs
    if (!rst_ni) begin
      state_q         <= StIdle;
      count_q         <= '0;
      sqrt_q          <= 1'b0;
      rcp_next_q      <= 1'b0;
      rem_q           <= '0;
      root_q          <= '0;
      rad_q           <= '0;
      divisor_q       <= '0;
      sign_q          <= 1'b0;
      exp_q           <= '0;
      special_q       <= 1'b0;
      special_value_q <= '0;
      tag_q           <= '0;
      result_q        <= '0;
    end else begin
      state_q         <= state_d;
      count_q         <= count_d;
      sqrt_q          <= sqrt_d;
      rcp_next_q      <= rcp_next_d;
      rem_q           <= rem_d;
      root_q          <= root_d;
      rad_q           <= rad_d;
      divisor_q       <= divisor_d;
      sign_q          <= sign_d;
      exp_q           <= exp_d;
      special_q       <= special_d;
      special_value_q <= special_value_d;
      tag_q           <= tag_d;
      result_q        <= result_d;
    end
  end

  assign rsp_valid_o  = state_q == StDone;
  assign rsp_o.tag    = tag_q;
  assign rsp_o.result = rpu_pkg::FpOperandBits'(result_q);

  // The divisor's sign and exponent enter through load_sign and load_exp; operand
  // bits above the format's width carry nothing (fp_req_t); no op has a third operand.
  logic unused_c;
  assign unused_c = ^req_i.c;
  if (Width < rpu_pkg::FpOperandBits) begin : g_unused_high
    logic unused_high;
    assign unused_high = ^{req_i.a[rpu_pkg::FpOperandBits-1:Width],
                           req_i.b[rpu_pkg::FpOperandBits-1:Width]};
  end

endmodule
