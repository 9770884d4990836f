// The shader core's special-function unit (docs/chip.md "Shader core"): rcp, rsq and
// sqrt of one thread's instruction at a time on Units rpu_fp_divsqrt dividers. Divider
// k takes the written lanes k, k + Units, ... in turn, so the lanes a write mask leaves
// out cost nothing; a divider is iterative (one operation in flight), so a thread's
// instruction takes ceil(written lanes / Units) divider operations back to back. The
// result (format values; the core widens them) leaves with the request's tag.
module rpu_spu_sfu #(
  parameter int unsigned ExpBits  = rpu_pkg::FormatFp32ExponentBits,
  parameter int unsigned FracBits = rpu_pkg::FormatFp32FractionBits,
  parameter int unsigned Units    = 1,
  parameter int unsigned Depth    = 4,
  parameter int unsigned TagBits  = 1
) (
  input  logic               clk_i,
  input  logic               rst_ni,

  input  logic               in_valid_i,
  output logic               in_ready_o,
  input  logic [TagBits-1:0] in_tag_i,
  input  logic [rpu_pkg::FpOpBits-1:0] in_op_i,  // FpOpRcp, FpOpRsqrt or FpOpSqrt
  input  logic [3:0]         in_wmask_i,
  input  logic [127:0]       in_a_i,      // format values, right-aligned per lane

  output logic               out_valid_o,
  input  logic               out_ready_i,
  output logic [TagBits-1:0] out_tag_o,
  output logic [127:0]       out_value_o, // the written lanes' results, other lanes 0

  output logic [$clog2(Depth+1)-1:0] free_o  // entries the queue can still take
);

  localparam int unsigned EntryBits = TagBits + rpu_pkg::FpOpBits + 4 + 128;
  localparam int unsigned CountBits = $clog2(Depth + 1);

  // The queue of thread instructions; the head is the one being computed.
  logic                   head_valid, head_pop;
  logic [EntryBits-1:0]   head;
  logic [TagBits-1:0]     head_tag;
  logic [rpu_pkg::FpOpBits-1:0] head_op;
  logic [3:0]             head_wmask;
  logic [127:0]           head_a;
  logic [CountBits-1:0]   count_d, count_q;

  rpu_fifo #(.Width(EntryBits), .Depth(Depth)) u_queue (
    .clk_i, .rst_ni,
    .in_valid_i, .in_ready_o, .in_data_i({in_tag_i, in_op_i, in_wmask_i, in_a_i}),
    .out_valid_o(head_valid), .out_ready_i(head_pop), .out_data_o(head)
  );
  assign {head_tag, head_op, head_wmask, head_a} = head;

  always_comb begin : count_queue
    count_d = count_q;
    if (in_valid_i && in_ready_o && !head_pop) count_d = count_q + CountBits'(1);
    else if (head_pop && !(in_valid_i && in_ready_o)) count_d = count_q - CountBits'(1);
  end
  assign free_o = CountBits'(Depth) - count_q;

  // Per lane of the head: sent to its divider, and its result in.
  logic [3:0]   sent_d, sent_q, done_d, done_q;
  logic [127:0] value_d, value_q;
  logic [3:0]   send, got;           // this cycle
  logic [32*Units-1:0] unit_result;

  for (genvar k = 0; k < Units; k++) begin : g_unit
    // The lowest written lane of this divider's share not yet sent.
    logic [3:0]             mine, todo;
    logic [1:0]             lane;
    logic                   busy_d, busy_q;  // an operation of the head is in this divider
    logic [1:0]             lane_d, lane_q;
    // Request {op, tag, a, b, c} and response {tag, result} as vectors: Yosys 0.23
    // resolves no struct fields of signals declared in a generate block.
    logic [rpu_pkg::FpReqBits-1:0] req;
    logic [rpu_pkg::FpRspBits-1:0] rsp;
    logic                   req_valid, req_ready, rsp_valid;

    for (genvar l = 0; l < 4; l++) begin : g_share
      assign mine[l] = (l % Units) == k;
    end
    assign todo = head_wmask & mine & ~sent_q;
    assign lane = todo[0] ? 2'd0 : todo[1] ? 2'd1 : todo[2] ? 2'd2 : 2'd3;
    assign req_valid = head_valid && todo != '0 && !busy_q;

    assign req = {head_op, rpu_pkg::FpTagBits'(0), head_a[32*lane +: 32], 64'd0};

    rpu_fp_divsqrt #(.ExpBits(ExpBits), .FracBits(FracBits)) u_divsqrt (
      .clk_i, .rst_ni,
      .req_valid_i(req_valid), .req_ready_o(req_ready), .req_i(req),
      .rsp_valid_o(rsp_valid), .rsp_ready_i(1'b1), .rsp_o(rsp)
    );

    always_comb begin : track_divider
      busy_d = busy_q;
      lane_d = lane_q;
      if (req_valid && req_ready) begin
        busy_d = 1'b1;
        lane_d = lane;
      end else if (rsp_valid) begin
        busy_d = 1'b0;
      end
    end

    always_ff @(posedge clk_i or negedge rst_ni) begin : divider_regs
      if (!rst_ni) begin
        busy_q <= 1'b0;
        lane_q <= '0;
      end else begin
        busy_q <= busy_d;
        lane_q <= lane_d;
      end
    end

    for (genvar l = 0; l < 4; l++) begin : g_lane
      if (l % Units == k) begin : g_mine
        assign send[l] = req_valid && req_ready && lane == 2'(l);
        assign got[l]  = rsp_valid && lane_q == 2'(l);
      end
    end
    assign unit_result[32*k +: 32] = rsp[31:0];

    logic unused;
    assign unused = ^rsp[32 +: rpu_pkg::FpTagBits];
  end

  assign out_valid_o = head_valid && (head_wmask & ~done_q) == '0;
  assign out_tag_o   = head_tag;
  assign out_value_o = value_q;
  assign head_pop    = out_valid_o && out_ready_i;

  always_comb begin : gather_results
    sent_d  = sent_q | send;
    done_d  = done_q | got;
    value_d = value_q;
    for (int l = 0; l < 4; l++) begin
      if (got[l]) value_d[32*l +: 32] = unit_result[32*(l % Units) +: 32];
    end
    if (head_pop) begin
      sent_d  = '0;
      done_d  = '0;
      value_d = '0;
    end
  end

  always_ff @(posedge clk_i or negedge rst_ni) begin : regs
    if (!rst_ni) begin
      sent_q  <= '0;
      done_q  <= '0;
      value_q <= '0;
      count_q <= '0;
    end else begin
      sent_q  <= sent_d;
      done_q  <= done_d;
      value_q <= value_d;
      count_q <= count_d;
    end
  end

endmodule
