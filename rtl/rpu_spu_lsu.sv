// The shader core's load/store unit (docs/chip.md "Shader core"): the core's memory
// accesses in program order onto one cache port. An access is 4 or 16 bytes at a
// 4-byte-aligned address; the cache port moves aligned MemLineBytes pieces, so an
// access may take two. Loads wait in one of Slots miss registers for their pieces
// (answered by tag in any order) and leave as soon as they are whole, in any order;
// stores are posted. Since the accesses reach the cache in program order and the cache
// keeps that order towards memory, a load after a store to the same address reads the
// stored value (a thread's own pixel, its stack).
module rpu_spu_lsu #(
  parameter int unsigned TagBits = 1,  // what the core needs back with a load's data
  parameter int unsigned Depth   = 4,
  localparam int unsigned Slots     = rpu_pkg::LsuLoadSlots,
  localparam int unsigned CountBits = $clog2(Depth + 1)
) (
  input  logic                  clk_i,
  input  logic                  rst_ni,

  input  logic                  in_valid_i,
  output logic                  in_ready_o,
  input  logic                  in_store_i,
  input  logic [TagBits-1:0]    in_tag_i,
  input  logic [31:0]           in_addr_i,
  input  logic                  in_wide_i,   // 16 bytes, else 4
  input  logic [3:0]            in_words_i,  // a store's words (bit j: the word at addr + 4j)
  input  logic [127:0]          in_data_i,   // a store's words, word j at [32j +: 32]
  output logic [CountBits-1:0]  free_o,      // entries the queue can still take

  output logic                  cache_req_valid_o,
  input  logic                  cache_req_ready_i,
  output rpu_pkg::cache_req_t   cache_req_o,
  input  logic                  cache_rsp_valid_i,
  output logic                  cache_rsp_ready_o,
  input  rpu_pkg::cache_rsp_t   cache_rsp_i,

  output logic                  out_valid_o,
  input  logic                  out_ready_i,
  output logic [TagBits-1:0]    out_tag_o,
  output logic [127:0]          out_data_o,  // word j = the word at addr + 4j (word 0 alone for 4 bytes)

  output logic                  idle_o       // nothing queued, sent or awaited
);

  localparam int unsigned EntryBits = 1 + TagBits + 32 + 1 + 4 + 128;
  localparam int unsigned SlotBits = $clog2(Slots);
  localparam int unsigned PieceBytes = rpu_pkg::MemLineBytes;
  localparam int unsigned PieceWords = PieceBytes / 4;
  localparam int unsigned OffsetBits = $clog2(PieceBytes);

  // ---------------------------------------------------------------------------------
  // The queue; its head is split into pieces.
  // ---------------------------------------------------------------------------------
  logic                 head_valid, head_pop;
  logic [EntryBits-1:0] head;
  logic                 h_store, h_wide;
  logic [TagBits-1:0]   h_tag;
  logic [31:0]          h_addr;
  logic [3:0]           h_words;
  logic [127:0]         h_data;
  logic [CountBits-1:0] count_d, count_q;

  rpu_fifo #(.Width(EntryBits), .Depth(Depth)) u_queue (
    .clk_i, .rst_ni,
    .in_valid_i, .in_ready_o,
    .in_data_i({in_store_i, in_tag_i, in_addr_i, in_wide_i, in_words_i, in_data_i}),
    .out_valid_o(head_valid), .out_ready_i(head_pop), .out_data_o(head)
  );
  assign {h_store, h_tag, h_addr, h_wide, h_words, h_data} = head;

  always_comb begin : count_queue
    count_d = count_q;
    if (in_valid_i && in_ready_o && !head_pop) count_d = count_q + CountBits'(1);
    else if (head_pop && !(in_valid_i && in_ready_o)) count_d = count_q - CountBits'(1);
  end
  assign free_o = CountBits'(Depth) - count_q;

  // Word j of the access is word (offset + j) of the pieces from the first on.
  logic [1:0]                 offset;
  logic [2*PieceWords-1:0]    span;       // the words of the two pieces the access covers
  logic [2*PieceWords*32-1:0] span_data;  // a store's words at their place in the pieces
  assign offset = h_addr[OffsetBits-1:2];
  always_comb begin : place_words
    span      = '0;
    span_data = '0;
    for (int j = 0; j < 4; j++) begin
      if (j == 0 || h_wide) begin
        span[32'(offset) + j] = h_store ? h_words[j] : 1'b1;
        span_data[32*(32'(offset) + j) +: 32] = h_data[32*j +: 32];
      end
    end
  end

  logic [31:0] first_addr;
  logic [1:0]  piece_needed;
  assign first_addr   = {h_addr[31:OffsetBits], OffsetBits'(0)};
  assign piece_needed = {|span[PieceWords +: PieceWords], |span[0 +: PieceWords]};

  // ---------------------------------------------------------------------------------
  // Load slots.
  // ---------------------------------------------------------------------------------
  logic [Slots-1:0]            busy_d, busy_q;
  logic [2*Slots-1:0]          wait_d, wait_q;      // pieces still to come
  logic [Slots*TagBits-1:0]    tag_d, tag_q;
  logic [2*Slots-1:0]          offset_d, offset_q;
  logic [Slots*2*PieceWords*32-1:0] data_d, data_q;

  logic                free_slot_found;
  logic [SlotBits-1:0] free_slot;
  always_comb begin : find_free_slot
    free_slot_found = 1'b0;
    free_slot       = '0;
    for (int s = Slots - 1; s >= 0; s--) begin
      if (!busy_q[s]) begin
        free_slot_found = 1'b1;
        free_slot       = SlotBits'(s);
      end
    end
  end

  // The head's pieces go out in order; a load first takes a slot.
  logic                sent_first_d, sent_first_q;  // the head's first needed piece is out
  logic [SlotBits-1:0] head_slot_d, head_slot_q;
  logic                piece;                       // which piece goes now
  logic                can_send;
  assign piece    = sent_first_q || !piece_needed[0];
  assign can_send = head_valid && (h_store || sent_first_q || free_slot_found);
  assign cache_req_valid_o = can_send;
  always_comb begin : cache_request
    cache_req_o       = '0;
    cache_req_o.addr  = piece ? first_addr + 32'(PieceBytes) : first_addr;
    cache_req_o.write = h_store;
    cache_req_o.tag   = rpu_pkg::CacheTagBits'({sent_first_q ? head_slot_q : free_slot, piece});
    cache_req_o.wmask = h_store ? span[PieceWords*piece +: PieceWords] : '0;
    cache_req_o.data  = span_data[PieceWords*32*piece +: PieceWords*32];
  end

  logic sent, last_piece;
  assign sent       = cache_req_valid_o && cache_req_ready_i;
  assign last_piece = piece || !piece_needed[1];
  assign head_pop   = sent && last_piece;

  always_comb begin : track_head
    sent_first_d = sent_first_q;
    head_slot_d  = head_slot_q;
    if (sent && !sent_first_q) head_slot_d = free_slot;
    if (sent) sent_first_d = !last_piece;
  end

  // Answers, and the whole loads that leave.
  logic                pick_found;
  logic [SlotBits-1:0] pick;
  always_comb begin : pick_done_slot
    pick_found = 1'b0;
    pick       = '0;
    for (int s = Slots - 1; s >= 0; s--) begin
      if (busy_q[s] && wait_q[2*s +: 2] == 2'b00) begin
        pick_found = 1'b1;
        pick       = SlotBits'(s);
      end
    end
  end
  assign cache_rsp_ready_o = 1'b1;
  assign out_valid_o = pick_found;
  assign out_tag_o   = tag_q[TagBits*pick +: TagBits];
  always_comb begin : gather_load
    // Word j of the load is word offset + j of the slot's two pieces.
    out_data_o = '0;
    for (int j = 0; j < 4; j++) begin
      out_data_o[32*j +: 32] = data_q[2*PieceWords*32*pick + 32*(32'(offset_q[2*pick +: 2]) + j) +: 32];
    end
  end

  logic [SlotBits-1:0] rsp_slot;
  logic                rsp_piece;
  assign {rsp_slot, rsp_piece} = cache_rsp_i.tag[SlotBits:0];

  always_comb begin : next_slots
    busy_d   = busy_q;
    wait_d   = wait_q;
    tag_d    = tag_q;
    offset_d = offset_q;
    data_d   = data_q;
    if (sent && !h_store && !sent_first_q) begin
      busy_d[free_slot]                   = 1'b1;
      wait_d[2*free_slot +: 2]            = piece_needed;
      tag_d[TagBits*free_slot +: TagBits] = h_tag;
      offset_d[2*free_slot +: 2]          = offset;
    end
    if (cache_rsp_valid_i) begin
      wait_d[2*rsp_slot + 32'(rsp_piece)] = 1'b0;
      data_d[2*PieceWords*32*rsp_slot + PieceWords*32*32'(rsp_piece) +: PieceWords*32] = cache_rsp_i.data;
    end
    if (out_valid_o && out_ready_i) busy_d[pick] = 1'b0;
  end

  always_ff @(posedge clk_i or negedge rst_ni) begin : regs
    if (!rst_ni) begin
      busy_q       <= '0;
      wait_q       <= '0;
      tag_q        <= '0;
      offset_q     <= '0;
      data_q       <= '0;
      sent_first_q <= 1'b0;
      head_slot_q  <= '0;
      count_q      <= '0;
    end else begin
      busy_q       <= busy_d;
      wait_q       <= wait_d;
      tag_q        <= tag_d;
      offset_q     <= offset_d;
      data_q       <= data_d;
      sent_first_q <= sent_first_d;
      head_slot_q  <= head_slot_d;
      count_q      <= count_d;
    end
  end

  assign idle_o = !head_valid && busy_q == '0;

  // The core sends only aligned addresses (it faults on the others).
  logic unused;
  assign unused = ^{h_addr[1:0], cache_rsp_i.tag[rpu_pkg::CacheTagBits-1:SlotBits+1]};

`ifndef SYNTHESIS
  initial begin
    assert (SlotBits + 1 < rpu_pkg::CacheTagBits)
      else $fatal(1, "rpu_spu_lsu: %0d load slots of two pieces need more than CacheTagBits %0d", Slots,
                  rpu_pkg::CacheTagBits);
  end
  always_ff @(posedge clk_i or negedge rst_ni) begin : check_answers
    if (rst_ni && cache_rsp_valid_i) begin
      assert (busy_q[rsp_slot] && wait_q[2*rsp_slot + 32'(rsp_piece)])
        else $error("rpu_spu_lsu: an answer with tag %0h for no piece awaited", cache_rsp_i.tag);
    end
  end
`endif

endmodule
