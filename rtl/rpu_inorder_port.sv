// A traversal unit's memory port (mem_req/mem_rsp: reads of MemLineBytes lines) onto a
// cache port (answered by tag in any order), answering in request order. Each request
// leaves at once, in the cycle it is taken, tagged with its place in a reorder buffer of
// 2^TagBits entries; an answer waits there until every older one has left, and leaves
// with the unit's own tag. A walker sends an intersection record's lines back to back
// (rtl/rpu_tu.sv), three at most in flight; TagBits is what a cache arbiter leaves of
// the cache's tag (rpu_cache_arbiter's OwnTagBits).
module rpu_inorder_port #(
  parameter int unsigned TagBits = rpu_pkg::CacheTagBits,
  localparam int unsigned Entries = 1 << TagBits
) (
  input  logic                clk_i,
  input  logic                rst_ni,

  input  logic                mem_req_valid_i,
  output logic                mem_req_ready_o,
  input  rpu_pkg::mem_req_t   mem_req_i,
  output logic                mem_rsp_valid_o,
  input  logic                mem_rsp_ready_i,
  output rpu_pkg::mem_rsp_t   mem_rsp_o,

  output logic                cache_req_valid_o,
  input  logic                cache_req_ready_i,
  output rpu_pkg::cache_req_t cache_req_o,
  input  logic                cache_rsp_valid_i,
  output logic                cache_rsp_ready_o,
  input  rpu_pkg::cache_rsp_t cache_rsp_i,

  output logic                idle_o  // nothing in flight
);

  localparam int unsigned LineBits  = 8 * rpu_pkg::MemLineBytes;
  localparam int unsigned CountBits = TagBits + 1;

  logic [TagBits-1:0]        head_d, head_q;  // the oldest entry: answered next
  logic [TagBits-1:0]        tail_d, tail_q;  // the next request's entry
  logic [CountBits-1:0]      count_d, count_q;
  logic [Entries-1:0]        done_d, done_q;  // its answer is here
  logic [Entries*LineBits-1:0] line_d, line_q;
  logic [Entries*rpu_pkg::CacheTagBits-1:0] unit_tag_d, unit_tag_q;  // the unit's tag of each entry

  logic room, push, pop;
  logic [TagBits-1:0] rsp_entry;
  assign room      = count_q != CountBits'(Entries);
  assign rsp_entry = cache_rsp_i.tag[TagBits-1:0];

  assign cache_req_valid_o = mem_req_valid_i && room;
  assign mem_req_ready_o   = cache_req_ready_i && room;
  always_comb begin : cache_request
    cache_req_o      = '0;
    cache_req_o.tag  = rpu_pkg::CacheTagBits'(tail_q);
    cache_req_o.addr = mem_req_i.addr;
  end
  assign cache_rsp_ready_o = 1'b1;  // every answer has its entry

  assign mem_rsp_valid_o = done_q[head_q];
  assign mem_rsp_o.tag   = unit_tag_q[32'(head_q)*rpu_pkg::CacheTagBits +: rpu_pkg::CacheTagBits];
  assign mem_rsp_o.data  = line_q[32'(head_q)*LineBits +: LineBits];

  assign push = mem_req_valid_i && mem_req_ready_o;
  assign pop  = mem_rsp_valid_o && mem_rsp_ready_i;

  always_comb begin : next_entries
    head_d  = pop ? head_q + TagBits'(1) : head_q;
    tail_d  = push ? tail_q + TagBits'(1) : tail_q;
    count_d = count_q + CountBits'(push) - CountBits'(pop);
    done_d  = done_q;
    line_d  = line_q;
    unit_tag_d = unit_tag_q;
    if (push) unit_tag_d[32'(tail_q)*rpu_pkg::CacheTagBits +: rpu_pkg::CacheTagBits] = mem_req_i.tag;
    if (pop) done_d[head_q] = 1'b0;
    if (cache_rsp_valid_i) begin
      done_d[rsp_entry] = 1'b1;
      line_d[32'(rsp_entry)*LineBits +: LineBits] = cache_rsp_i.data;
    end
  end

  always_ff @(posedge clk_i or negedge rst_ni) begin : regs
    if (!rst_ni) begin
      head_q  <= '0;
      tail_q  <= '0;
      count_q <= '0;
      done_q  <= '0;
      line_q  <= '0;
      unit_tag_q <= '0;
    end else begin
      head_q  <= head_d;
      tail_q  <= tail_d;
      count_q <= count_d;
      done_q  <= done_d;
      line_q  <= line_d;
      unit_tag_q <= unit_tag_d;
    end
  end

  assign idle_o = count_q == '0;

`ifndef SYNTHESIS
  initial begin
    assert (TagBits >= 1 && TagBits <= rpu_pkg::CacheTagBits)
      else $fatal(1, "rpu_inorder_port: TagBits %0d outside 1..%0d", TagBits, rpu_pkg::CacheTagBits);
  end
  // An answer belongs to an entry in flight (between head and tail) not yet answered.
  logic [TagBits-1:0] age;
  assign age = rsp_entry - head_q;
  always_ff @(posedge clk_i or negedge rst_ni) begin : check_answers
    if (rst_ni && cache_rsp_valid_i) begin
      assert (32'(cache_rsp_i.tag) < Entries && 32'(age) < 32'(count_q) && !done_q[rsp_entry])
        else $error("rpu_inorder_port: an answer with tag %0h for no request in flight", cache_rsp_i.tag);
    end
  end
`endif

endmodule
