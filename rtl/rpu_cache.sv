// A set-associative cache of DramLineBytes lines, write-through or write-back, between
// MemLineBytes requesters (a cache port: cache_req/cache_rsp) and the chip's memory port
// (dram_req/dram_rsp), docs/memory-system.md. A named configuration's
// {node,triangle,data}_cache.{bytes,ways,hit_latency,mshrs,write_back} are its parameters.
//
// Every decision is made in the cycle a request is taken, against registers that
// already hold everything taken before it, and one operation a cycle uses the lookup,
// in this order of precedence:
//   1. a replay: a read whose line has just been installed is answered (the lowest
//      tag first), through the same data-array read as a hit;
//   2. an install: a line read from memory is written into its set's least recently
//      used way (an invalid way first), its miss register freed and its waiting reads
//      marked for replay; never while a replay is pending, so an install cannot evict
//      the line a replay is about to read; a dirty victim (WriteBack) is read out in the
//      same cycle into the eviction buffer, so the install waits while that is busy;
//   3. a flush step (flush_i, WriteBack): the walk over every way of every set moves to
//      the next way, reading a dirty line into the eviction buffer first;
//   4. a request from the port (none is taken while flush_i is high):
//      - a read of a present line (hit) reads the data array and is answered
//        HitLatency cycles after it was taken, one a cycle;
//      - a read of a line whose fill is in flight (merged) waits for that fill;
//      - any other read (miss) takes a free miss register and queues one line read;
//        with none free the port stalls;
//      - a write updates the words of a present line and, write-through, queues the
//        write to memory, or, write-back, marks the line dirty; a write to an absent
//        line is queued to memory either way (no allocation); a write to a line whose
//        fill is in flight stalls the port until the fill is installed and its reads
//        answered, so that the fill cannot overwrite newer data and those reads see
//        the older data.
// The memory requests leave through one FIFO in the order their requests were taken,
// so a read that misses after a write to its line reads that write back from memory.
// An evicted dirty line leaves from the eviction buffer, ahead of the FIFO: every
// request the FIFO holds for its line was taken before the line's fill was installed,
// and so has left already, and any taken after the eviction is behind it.
// Reads waiting for a fill are kept per tag: a tag is in flight at most once (the
// requesters guarantee it), so 2^CacheTagBits entries hold every one.
module rpu_cache #(
  parameter int unsigned Bytes      = rpu_pkg::ConfigTinyDataCacheBytes,
  parameter int unsigned Ways       = rpu_pkg::ConfigTinyDataCacheWays,
  parameter int unsigned HitLatency = rpu_pkg::ConfigTinyDataCacheHitLatency,
  parameter int unsigned Mshrs      = rpu_pkg::ConfigTinyDataCacheMshrs,
  parameter int unsigned WriteBack  = rpu_pkg::ConfigTinyDataCacheWriteBack,
  parameter int unsigned CacheId    = 0,  // the high bits of its memory-port tags (rpu_mem_arbiter's port)
  parameter int unsigned DramQueue  = rpu_pkg::CacheDramQueue  // memory requests queued towards the port
) (
  input  logic                     clk_i,
  input  logic                     rst_ni,

  // Write every dirty line to memory (WriteBack); held until idle_o, and requests wait.
  input  logic                     flush_i,

  input  logic                     req_valid_i,
  output logic                     req_ready_o,
  input  rpu_pkg::cache_req_t      req_i,
  output logic                     rsp_valid_o,
  input  logic                     rsp_ready_i,
  output rpu_pkg::cache_rsp_t      rsp_o,

  output logic                     dram_req_valid_o,
  input  logic                     dram_req_ready_i,
  output rpu_pkg::dram_req_t       dram_req_o,
  input  logic                     dram_rsp_valid_i,
  output logic                     dram_rsp_ready_o,
  input  rpu_pkg::dram_rsp_t       dram_rsp_i,

  output rpu_pkg::cache_counters_t counters_o,
  output logic                     idle_o,  // nothing taken is still owed or in flight
  output logic                     dirty_o  // a line is dirty (WriteBack): a flush has work
);

  localparam int unsigned LineBytes     = rpu_pkg::DramLineBytes;
  localparam int unsigned PieceBytes    = rpu_pkg::MemLineBytes;
  localparam int unsigned LineWords     = LineBytes / 4;
  localparam int unsigned PieceWords    = PieceBytes / 4;
  localparam int unsigned PieceBits     = $clog2(LineBytes / PieceBytes);
  localparam int unsigned OffsetBits    = $clog2(LineBytes);
  localparam int unsigned Sets          = Bytes / (LineBytes * Ways);
  localparam int unsigned IndexBits     = $clog2(Sets);
  localparam int unsigned SetBits       = Sets > 1 ? IndexBits : 1;
  localparam int unsigned LineAddrBits  = 32 - OffsetBits;
  localparam int unsigned PieceAddrBits = 32 - $clog2(PieceBytes);
  localparam int unsigned TagBits       = LineAddrBits - IndexBits;
  localparam int unsigned WayBits       = Ways > 1 ? $clog2(Ways) : 1;
  localparam int unsigned EntryBits     = Sets * Ways > 1 ? $clog2(Sets * Ways) : 1;
  // The LRU order of a set: bit p(i, j), i < j, says way i was used after way j. All
  // zero (reset) is the order 0 oldest ... Ways-1 newest, a valid one.
  localparam int unsigned PairBits      = Ways > 1 ? Ways * (Ways - 1) / 2 : 1;
  localparam int unsigned MshrBits      = Mshrs > 1 ? $clog2(Mshrs) : 1;
  localparam int unsigned CacheIdBits   = rpu_pkg::DramTagBits - rpu_pkg::DramMshrBits;
  localparam int unsigned Tags          = 1 << rpu_pkg::CacheTagBits;
  localparam int unsigned RamDepth      = Sets * Ways;
  localparam int unsigned RamAddrBits   = RamDepth > 1 ? $clog2(RamDepth) : 1;
  // Answers in flight: HitLatency - 1 cycles in the data array and the delay stages,
  // one in the FIFO; so many credits keep one answer a cycle flowing.
  localparam int unsigned RspDepth      = HitLatency + 1;
  localparam int unsigned CreditBits    = $clog2(RspDepth + 1);
  localparam int unsigned RspEntryBits  = rpu_pkg::CacheTagBits + 32 * PieceWords;
  localparam int unsigned Delay         = HitLatency - 2;
  localparam int unsigned DramEntryBits = 1 + LineAddrBits + MshrBits + PieceBits + PieceWords + 32 * PieceWords;

  // ---------------------------------------------------------------------------------
  // State.
  // ---------------------------------------------------------------------------------
  // Valid bits are flops (reset); way w of set s at entry s*Ways + w. Tags and LRU order
  // are memories read in the lookup's cycle (g_way below, set_order): written by an
  // install or a touch alone, a set at a time, they need no shifter as wide as the
  // array in synthesis and no copy of it each cycle in simulation.
  logic [Sets*Ways-1:0]          valid_d, valid_q;
  logic [Mshrs-1:0]              mshr_valid_d, mshr_valid_q;
  logic [Mshrs*LineAddrBits-1:0] mshr_line_d, mshr_line_q;
  // Reads by tag: waiting for a fill, or answered next by a replay.
  logic [Tags-1:0]               wait_d, wait_q, replay_d, replay_q;
  logic [Tags*MshrBits-1:0]      wait_mshr_d, wait_mshr_q;
  logic [Tags*PieceAddrBits-1:0] wait_addr_d, wait_addr_q;
  logic [CreditBits-1:0]         credit_d, credit_q;
  rpu_pkg::cache_counters_t      counters_d, counters_q;
  // Write-back: a dirty bit per way (flops, reset, beside the valid bits); the flush's
  // walk, way by way, set by set; and the eviction buffer, which holds one dirty line
  // from the cycle after its data-array read (ev_read_q: the words arrive) until the
  // memory port takes it (ev_valid_q).
  logic [Sets*Ways-1:0]          dirty_d, dirty_q;
  logic [SetBits-1:0]            flush_set_d, flush_set_q;
  logic [WayBits-1:0]            flush_way_d, flush_way_q;
  logic                          flush_done_d, flush_done_q;
  logic                          ev_read_d, ev_read_q, ev_valid_d, ev_valid_q;
  logic [LineAddrBits-1:0]       ev_line_d, ev_line_q;
  logic [32*LineWords-1:0]       ev_data_d, ev_data_q;

  // ---------------------------------------------------------------------------------
  // Which operation looks up this cycle.
  // ---------------------------------------------------------------------------------
  logic                            replay_pending, credit_ok;
  logic [rpu_pkg::CacheTagBits-1:0] replay_tag;
  logic                            replay_go, install_go, front_free, flush_look, flush_go;
  logic [MshrBits-1:0]             fill_mshr;
  logic                            ev_free, victim_dirty, flush_dirty;

  always_comb begin : pick_replay
    replay_pending = 1'b0;
    replay_tag     = '0;
    for (int t = Tags - 1; t >= 0; t--) begin
      if (replay_q[t]) begin
        replay_pending = 1'b1;
        replay_tag     = rpu_pkg::CacheTagBits'(t);
      end
    end
  end

  assign credit_ok  = credit_q != '0;
  assign fill_mshr  = dram_rsp_i.tag[MshrBits-1:0];
  assign replay_go  = replay_pending && credit_ok;
  assign ev_free    = !ev_read_q && !ev_valid_q;
  assign install_go = !replay_pending && dram_rsp_valid_i && (!victim_dirty || ev_free);
  assign front_free = !replay_pending && !dram_rsp_valid_i;
  assign flush_look = front_free && flush_i && WriteBack != 0 && !flush_done_q;
  assign flush_go   = flush_look && (!flush_dirty || ev_free);
  assign dram_rsp_ready_o = install_go;

  logic [31:0] look_addr;
  always_comb begin : pick_look_addr
    if (replay_pending) begin
      look_addr = {wait_addr_q[32'(replay_tag)*PieceAddrBits +: PieceAddrBits], 4'b0};
    end else if (dram_rsp_valid_i) begin
      look_addr = {mshr_line_q[32'(fill_mshr)*LineAddrBits +: LineAddrBits], OffsetBits'(0)};
    end else if (flush_i && WriteBack != 0) begin
      look_addr = 32'(flush_set_q) << OffsetBits;
    end else begin
      look_addr = req_i.addr;
    end
  end

  // ---------------------------------------------------------------------------------
  // The lookup: the set's ways, the miss registers, a free one, the set's LRU way.
  // ---------------------------------------------------------------------------------
  logic [SetBits-1:0]      look_set;
  logic [TagBits-1:0]      look_tag;
  logic [LineAddrBits-1:0] look_line;
  logic [PieceBits-1:0]    look_piece;
  assign look_set   = SetBits'((look_addr >> OffsetBits) & 32'(Sets - 1));
  assign look_tag   = TagBits'(look_addr >> (OffsetBits + IndexBits));
  assign look_line  = look_addr[31:OffsetBits];
  assign look_piece = look_addr[OffsetBits-1 -: PieceBits];

  logic [Ways-1:0]        set_valid, set_dirty;
  logic [Ways*TagBits-1:0] set_tags;
  logic [Ways-1:0]        hit_ways;
  logic                   hit;
  logic [WayBits-1:0]     hit_way;
  assign set_valid = valid_q[EntryBits'(look_set) * EntryBits'(Ways) +: Ways];
  assign set_dirty = dirty_q[EntryBits'(look_set) * EntryBits'(Ways) +: Ways];
  always_comb begin : match_ways
    hit     = 1'b0;
    hit_way = '0;
    for (int w = Ways - 1; w >= 0; w--) begin
      hit_ways[w] = set_valid[w] && set_tags[w*TagBits +: TagBits] == look_tag;
      if (hit_ways[w]) begin
        hit     = 1'b1;
        hit_way = WayBits'(w);
      end
    end
  end

  logic [Mshrs-1:0]    pending_mshrs;
  logic                pending, mshr_free;
  logic [MshrBits-1:0] pending_mshr, free_mshr;
  always_comb begin : match_mshrs
    pending      = 1'b0;
    pending_mshr = '0;
    mshr_free    = 1'b0;
    free_mshr    = '0;
    for (int m = Mshrs - 1; m >= 0; m--) begin
      pending_mshrs[m] = mshr_valid_q[m] && mshr_line_q[m*LineAddrBits +: LineAddrBits] == look_line;
      if (pending_mshrs[m]) begin
        pending      = 1'b1;
        pending_mshr = MshrBits'(m);
      end
      if (!mshr_valid_q[m]) begin
        mshr_free = 1'b1;
        free_mshr = MshrBits'(m);
      end
    end
  end

  // The victim: the lowest invalid way, else the way every other way was used after.
  logic [PairBits-1:0] set_order;
  logic [Ways-1:0]     oldest;
  logic [WayBits-1:0]  victim;
  always_comb begin : pick_victim
    for (int v = 0; v < Ways; v++) begin
      oldest[v] = 1'b1;
      for (int u = 0; u < Ways; u++) begin
        if (u < v) oldest[v] &= set_order[u*(2*Ways - u - 1)/2 + (v - u - 1)];
        if (u > v) oldest[v] &= !set_order[v*(2*Ways - v - 1)/2 + (u - v - 1)];
      end
    end
    victim = '0;
    for (int w = 0; w < Ways; w++) begin
      if (oldest[w]) victim = WayBits'(w);
    end
    for (int w = Ways - 1; w >= 0; w--) begin
      if (!set_valid[w]) victim = WayBits'(w);
    end
  end
  assign victim_dirty = WriteBack != 0 && set_valid[victim] && set_dirty[victim];
  assign flush_dirty  = set_valid[flush_way_q] && set_dirty[flush_way_q];

  // ---------------------------------------------------------------------------------
  // The request at the port.
  // ---------------------------------------------------------------------------------
  logic dq_ready;  // the memory-request FIFO has room
  logic take, take_read, hit_go, merge_go, miss_go, write_go, launch, write_kept;
  assign write_kept = WriteBack != 0 && hit;  // a write that stays in the cache
  always_comb begin : port_ready
    if (!front_free || flush_i) begin
      req_ready_o = 1'b0;
    end else if (req_i.write) begin
      req_ready_o = !pending && (dq_ready || write_kept);
    end else if (hit) begin
      req_ready_o = credit_ok;
    end else begin
      req_ready_o = pending || (mshr_free && dq_ready);
    end
  end
  assign take      = req_valid_i && req_ready_o;
  assign take_read = take && !req_i.write;
  assign hit_go    = take_read && hit;
  assign merge_go  = take_read && !hit && pending;
  assign miss_go   = take_read && !hit && !pending;
  assign write_go  = take && req_i.write;
  assign launch    = replay_go || hit_go;

  // The way this cycle uses: a fill's victim, else the way that hit. It becomes the
  // newest of its set, except for a write, which leaves the order as it is (the cycle
  // model's writes touch no tag).
  logic               touch;
  logic [WayBits-1:0] touch_way;
  assign touch     = launch || install_go;
  assign touch_way = install_go ? victim : hit_way;

  // A set's tags, one memory per way, and its LRU order. Neither has a reset: a tag is
  // read behind its valid bit, and the order only once every way of its set is valid,
  // by when the touch of one of each pair of ways has written the pair's bit. The array
  // writes are in their clocked processes, as in rpu_ram (the exception to _q <= _d).
  for (genvar w = 0; w < Ways; w++) begin : g_way
    logic [TagBits-1:0] tags_q [Sets];
    always_ff @(posedge clk_i) begin : write_tag
      if (install_go && victim == WayBits'(w)) tags_q[look_set] <= look_tag;
    end
    assign set_tags[w*TagBits +: TagBits] = tags_q[look_set];
  end

  logic [PairBits-1:0] order_q [Sets];
  logic [PairBits-1:0] touched_order;
  assign set_order = order_q[look_set];
  always_comb begin : touch_order
    touched_order = set_order;
    for (int i = 0; i < Ways; i++) begin
      for (int j = i + 1; j < Ways; j++) begin
        if (32'(touch_way) == i) touched_order[i*(2*Ways - i - 1)/2 + (j - i - 1)] = 1'b1;
        if (32'(touch_way) == j) touched_order[i*(2*Ways - i - 1)/2 + (j - i - 1)] = 1'b0;
      end
    end
  end
  always_ff @(posedge clk_i) begin : write_order
    if (touch) order_q[look_set] <= touched_order;
  end

  // ---------------------------------------------------------------------------------
  // The data array: one RAM per word of a line, so that a fill writes a line and a
  // write any words of a piece in one cycle. Word k of way w, set s is at w*Sets + s.
  // ---------------------------------------------------------------------------------
  // A hit reads its way; an install reads its victim and a flush step its way, for the
  // eviction buffer (the read returns the words from before the install's write).
  logic [RamAddrBits-1:0]  ram_waddr, ram_raddr;
  logic [LineWords-1:0]    ram_we;
  logic [32*LineWords-1:0] ram_wdata, ram_rdata;
  logic [WayBits-1:0]      read_way;
  assign read_way  = install_go ? victim : flush_look ? flush_way_q : hit_way;
  assign ram_waddr = RamAddrBits'(32'(touch_way) * Sets + 32'(look_set));
  assign ram_raddr = RamAddrBits'(32'(read_way) * Sets + 32'(look_set));
  for (genvar k = 0; k < LineWords; k++) begin : g_word
    assign ram_we[k] = install_go
                       || (write_go && hit && 32'(look_piece) == k / PieceWords && req_i.wmask[k % PieceWords]);
    assign ram_wdata[32*k +: 32] = install_go ? dram_rsp_i.data[32*k +: 32] : req_i.data[32*(k % PieceWords) +: 32];
    rpu_ram #(.Width(32), .Depth(RamDepth)) u_ram (
      .clk_i,
      .we_i(ram_we[k]), .waddr_i(ram_waddr), .wdata_i(ram_wdata[32*k +: 32]),
      .raddr_i(ram_raddr), .rdata_o(ram_rdata[32*k +: 32])
    );
  end

  // ---------------------------------------------------------------------------------
  // Answers: the piece read the cycle after its launch, HitLatency - 2 delay stages,
  // then a FIFO; a read launches only with a credit, so the FIFO never overflows.
  // ---------------------------------------------------------------------------------
  logic                             rd_valid_d, rd_valid_q;
  logic [rpu_pkg::CacheTagBits-1:0] rd_tag_d, rd_tag_q;
  logic [PieceBits-1:0]             rd_piece_d, rd_piece_q;
  logic [RspEntryBits-1:0]          rd_entry;
  assign rd_valid_d = launch;
  assign rd_tag_d   = replay_go ? replay_tag : req_i.tag;
  assign rd_piece_d = look_piece;
  assign rd_entry   = {rd_tag_q, ram_rdata[32*PieceWords*32'(rd_piece_q) +: 32*PieceWords]};

  logic                    answer_valid;
  logic [RspEntryBits-1:0] answer;
  if (Delay == 0) begin : g_no_delay
    assign answer_valid = rd_valid_q;
    assign answer       = rd_entry;
  end else begin : g_delay
    localparam int unsigned DelayBits = Delay * RspEntryBits;
    logic [Delay-1:0]     delay_valid_d, delay_valid_q;
    logic [DelayBits-1:0] delay_entry_d, delay_entry_q;
    assign delay_valid_d = (delay_valid_q << 1) | Delay'(rd_valid_q);
    assign delay_entry_d = (delay_entry_q << RspEntryBits) | DelayBits'(rd_entry);
    always_ff @(posedge clk_i or negedge rst_ni) begin : delay_regs
      if (!rst_ni) begin
        delay_valid_q <= '0;
        delay_entry_q <= '0;
      end else begin
        delay_valid_q <= delay_valid_d;
        delay_entry_q <= delay_entry_d;
      end
    end
    assign answer_valid = delay_valid_q[Delay-1];
    assign answer       = delay_entry_q[(Delay-1)*RspEntryBits +: RspEntryBits];
  end

  logic                    rsp_fifo_ready;
  logic [RspEntryBits-1:0] rsp_entry;
  rpu_fifo #(.Width(RspEntryBits), .Depth(RspDepth)) u_rsp_fifo (
    .clk_i, .rst_ni,
    .in_valid_i(answer_valid), .in_ready_o(rsp_fifo_ready), .in_data_i(answer),
    .out_valid_o(rsp_valid_o), .out_ready_i(rsp_ready_i), .out_data_o(rsp_entry)
  );
  assign {rsp_o.tag, rsp_o.data} = rsp_entry;

  always_comb begin : next_credit
    credit_d = credit_q;
    if (launch && !(rsp_valid_o && rsp_ready_i)) credit_d = credit_q - CreditBits'(1);
    if (!launch && rsp_valid_o && rsp_ready_i) credit_d = credit_q + CreditBits'(1);
  end

  // ---------------------------------------------------------------------------------
  // Memory requests, in the order their requests were taken.
  // ---------------------------------------------------------------------------------
  logic                     dq_valid;
  logic [DramEntryBits-1:0] dq_entry;
  logic                     dq_write;
  logic [LineAddrBits-1:0]  dq_line;
  logic [MshrBits-1:0]      dq_mshr;
  logic [PieceBits-1:0]     dq_piece;
  logic [PieceWords-1:0]    dq_wmask;
  logic [32*PieceWords-1:0] dq_data;
  rpu_fifo #(.Width(DramEntryBits), .Depth(DramQueue)) u_dram_queue (
    .clk_i, .rst_ni,
    .in_valid_i(miss_go || (write_go && !write_kept)), .in_ready_o(dq_ready),
    .in_data_i({write_go, look_line, free_mshr, look_piece, req_i.wmask, req_i.data}),
    .out_valid_o(dq_valid), .out_ready_i(dram_req_ready_i && !send_ev), .out_data_o(dq_entry)
  );
  assign {dq_write, dq_line, dq_mshr, dq_piece, dq_wmask, dq_data} = dq_entry;
  // The eviction buffer goes first, unless the queue's head is already offered: an
  // offered request stays until the port takes it (valid/ready).
  logic send_ev, dq_held_d, dq_held_q;
  assign send_ev          = ev_valid_q && !dq_held_q;
  assign dram_req_valid_o = ev_valid_q || dq_valid;
  assign dq_held_d        = dq_valid && !send_ev && !dram_req_ready_i;
  // A write's tag names the cache alone (writes are not answered).
  logic [MshrBits-1:0] dq_read_mshr;
  assign dq_read_mshr = dq_write ? '0 : dq_mshr;
  always_comb begin : dram_request
    dram_req_o       = '0;
    dram_req_o.tag   = {CacheIdBits'(CacheId), rpu_pkg::DramMshrBits'(dq_read_mshr)};
    dram_req_o.addr  = {dq_line, OffsetBits'(0)};
    dram_req_o.write = dq_write;
    if (send_ev) begin
      dram_req_o.tag   = {CacheIdBits'(CacheId), rpu_pkg::DramMshrBits'(0)};
      dram_req_o.addr  = {ev_line_q, OffsetBits'(0)};
      dram_req_o.write = 1'b1;
      dram_req_o.wmask = '1;
      dram_req_o.data  = ev_data_q;
    end else if (dq_write) begin
      dram_req_o.wmask = LineWords'(dq_wmask) << (PieceWords * 32'(dq_piece));
      dram_req_o.data  = (32*LineWords)'(dq_data) << (32 * PieceWords * 32'(dq_piece));
    end
  end

  // ---------------------------------------------------------------------------------
  // Write-back: evictions and the flush's walk.
  // ---------------------------------------------------------------------------------
  logic               ev_take;  // a dirty line is read into the eviction buffer
  logic [WayBits-1:0] ev_way;
  assign ev_take = (install_go && victim_dirty) || (flush_go && flush_dirty);
  assign ev_way  = install_go ? victim : flush_way_q;
  always_comb begin : next_eviction
    ev_read_d  = ev_take;
    ev_line_d  = ev_line_q;
    ev_data_d  = ev_data_q;
    ev_valid_d = ev_valid_q;
    if (ev_take) begin
      ev_line_d = (LineAddrBits'(set_tags[32'(ev_way)*TagBits +: TagBits]) << IndexBits) | LineAddrBits'(look_set);
    end
    if (ev_read_q) begin
      ev_data_d  = ram_rdata;
      ev_valid_d = 1'b1;
    end else if (send_ev && dram_req_ready_i) begin
      ev_valid_d = 1'b0;
    end
  end

  always_comb begin : next_flush
    flush_set_d  = flush_set_q;
    flush_way_d  = flush_way_q;
    flush_done_d = flush_done_q;
    if (!flush_i) begin
      flush_set_d  = '0;
      flush_way_d  = '0;
      flush_done_d = 1'b0;
    end else if (flush_go) begin
      if (32'(flush_way_q) == Ways - 1) begin
        flush_way_d = '0;
        if (32'(flush_set_q) == Sets - 1) begin
          flush_done_d = 1'b1;
        end else begin
          flush_set_d = flush_set_q + SetBits'(1);
        end
      end else begin
        flush_way_d = flush_way_q + WayBits'(1);
      end
    end
  end

  // ---------------------------------------------------------------------------------
  // Next state.
  // ---------------------------------------------------------------------------------
  always_comb begin : next_state
    valid_d      = valid_q;
    mshr_valid_d = mshr_valid_q;
    mshr_line_d  = mshr_line_q;
    wait_d       = wait_q;
    replay_d     = replay_q;
    wait_mshr_d  = wait_mshr_q;
    wait_addr_d  = wait_addr_q;
    dirty_d      = dirty_q;

    if (install_go) begin
      valid_d[EntryBits'(look_set) * EntryBits'(Ways) + EntryBits'(victim)] = 1'b1;
      dirty_d[EntryBits'(look_set) * EntryBits'(Ways) + EntryBits'(victim)] = 1'b0;
      mshr_valid_d[fill_mshr] = 1'b0;
      for (int t = 0; t < Tags; t++) begin
        if (wait_q[t] && wait_mshr_q[t*MshrBits +: MshrBits] == fill_mshr) begin
          wait_d[t]   = 1'b0;
          replay_d[t] = 1'b1;
        end
      end
    end

    if (replay_go) replay_d[replay_tag] = 1'b0;
    if (write_go && write_kept) dirty_d[EntryBits'(look_set) * EntryBits'(Ways) + EntryBits'(hit_way)] = 1'b1;
    if (flush_go && flush_dirty) dirty_d[EntryBits'(look_set) * EntryBits'(Ways) + EntryBits'(flush_way_q)] = 1'b0;

    if (miss_go) begin
      mshr_valid_d[free_mshr]                                 = 1'b1;
      mshr_line_d[32'(free_mshr)*LineAddrBits +: LineAddrBits] = look_line;
    end
    if (merge_go || miss_go) begin
      wait_d[req_i.tag]                                             = 1'b1;
      wait_mshr_d[32'(req_i.tag)*MshrBits +: MshrBits]              = miss_go ? free_mshr : pending_mshr;
      wait_addr_d[32'(req_i.tag)*PieceAddrBits +: PieceAddrBits]    = req_i.addr[31:32-PieceAddrBits];
    end
  end

  always_comb begin : count_events
    counters_d = counters_q;
    if (take_read) counters_d.accesses = counters_q.accesses + 32'd1;
    if (hit_go) counters_d.hits = counters_q.hits + 32'd1;
    if (merge_go) counters_d.merged = counters_q.merged + 32'd1;
    if (miss_go) counters_d.misses = counters_q.misses + 32'd1;
    if (write_go) counters_d.writes = counters_q.writes + 32'd1;
    if (ev_take) counters_d.write_backs = counters_q.write_backs + 32'd1;
    // A read miss the port could take but for a miss register (the lookup is the
    // port's only when no replay or install has it).
    if (front_free && req_valid_i && !req_i.write && !hit && !pending && !mshr_free) begin
      counters_d.mshr_wait = counters_q.mshr_wait + 32'd1;
    end
  end

  always_ff @(posedge clk_i or negedge rst_ni) begin : regs
    if (!rst_ni) begin
      valid_q      <= '0;
      mshr_valid_q <= '0;
      mshr_line_q  <= '0;
      wait_q       <= '0;
      replay_q     <= '0;
      wait_mshr_q  <= '0;
      wait_addr_q  <= '0;
      credit_q     <= CreditBits'(RspDepth);
      counters_q   <= '0;
      rd_valid_q   <= 1'b0;
      rd_tag_q     <= '0;
      rd_piece_q   <= '0;
      dirty_q      <= '0;
      flush_set_q  <= '0;
      flush_way_q  <= '0;
      flush_done_q <= 1'b0;
      ev_read_q    <= 1'b0;
      ev_valid_q   <= 1'b0;
      ev_line_q    <= '0;
      dq_held_q    <= 1'b0;
    end else begin
      valid_q      <= valid_d;
      mshr_valid_q <= mshr_valid_d;
      mshr_line_q  <= mshr_line_d;
      wait_q       <= wait_d;
      replay_q     <= replay_d;
      wait_mshr_q  <= wait_mshr_d;
      wait_addr_q  <= wait_addr_d;
      credit_q     <= credit_d;
      counters_q   <= counters_d;
      rd_valid_q   <= rd_valid_d;
      rd_tag_q     <= rd_tag_d;
      rd_piece_q   <= rd_piece_d;
      dirty_q      <= dirty_d;
      flush_set_q  <= flush_set_d;
      flush_way_q  <= flush_way_d;
      flush_done_q <= flush_done_d;
      ev_read_q    <= ev_read_d;
      ev_valid_q   <= ev_valid_d;
      ev_line_q    <= ev_line_d;
      dq_held_q    <= dq_held_d;
    end
  end

  // The eviction buffer's words have no reset: they are sent only behind ev_valid_q.
  always_ff @(posedge clk_i) begin : eviction_data
    ev_data_q <= ev_data_d;
  end

  assign counters_o = counters_q;
  assign idle_o = mshr_valid_q == '0 && wait_q == '0 && replay_q == '0 && credit_q == CreditBits'(RspDepth)
                  && !dq_valid && !ev_read_q && !ev_valid_q;
  assign dirty_o = (dirty_q & valid_q) != '0;

  // Requests are MemLineBytes-aligned; a fill's tag names this cache, which the
  // arbiter has already routed by (checked below).
  logic unused;
  assign unused = ^{req_i.addr[31-PieceAddrBits:0], dram_rsp_i.tag[rpu_pkg::DramTagBits-1:MshrBits], rsp_fifo_ready};

`ifndef SYNTHESIS
  initial begin
    assert (HitLatency >= 2) else $fatal(1, "rpu_cache: HitLatency %0d; the data array's read takes 2", HitLatency);
    assert (Sets * Ways * LineBytes == Bytes && (Sets & (Sets - 1)) == 0)
      else $fatal(1, "rpu_cache: %0d bytes are not a power-of-two number of sets of %0d ways", Bytes, Ways);
    assert (WriteBack <= 1) else $fatal(1, "rpu_cache: WriteBack %0d is not 0 or 1", WriteBack);
    assert (Mshrs <= (1 << rpu_pkg::DramMshrBits) && CacheId < (1 << CacheIdBits))
      else $fatal(1, "rpu_cache: %0d miss registers or cache id %0d do not fit a memory tag", Mshrs, CacheId);
  end

  // Read tags taken and not yet answered: a requester must not reuse one.
  logic [Tags-1:0] in_flight_q;
  always_ff @(posedge clk_i or negedge rst_ni) begin : check_invariants
    if (!rst_ni) begin
      in_flight_q <= '0;
    end else begin
      if (req_valid_i) begin
        assert (req_i.addr[31-PieceAddrBits:0] == '0) else $error("rpu_cache: request at %h not aligned", req_i.addr);
      end
      if (take_read) begin
        assert (!in_flight_q[req_i.tag]) else $error("rpu_cache: read tag %0h taken while in flight", req_i.tag);
      end
      if (dram_rsp_valid_i) begin
        assert (32'(dram_rsp_i.tag[rpu_pkg::DramTagBits-1:rpu_pkg::DramMshrBits]) == CacheId && 32'(fill_mshr) < Mshrs
                && mshr_valid_q[fill_mshr])
          else $error("rpu_cache %0d: a line read answer with tag %h for no miss register", CacheId, dram_rsp_i.tag);
      end
      assert (!replay_go || hit) else $error("rpu_cache: a replay missed its line");
      assert (WriteBack != 0 || dirty_q == '0) else $error("rpu_cache: a dirty line in a write-through cache");
      assert (!(ev_read_q && ev_valid_q)) else $error("rpu_cache: two lines in the eviction buffer");
      assert (!(hit && pending)) else $error("rpu_cache: a line both present and being filled");
      assert ($onehot0(hit_ways)) else $error("rpu_cache: a line in two ways of set %0d", look_set);
      assert (!answer_valid || rsp_fifo_ready) else $error("rpu_cache: the answer FIFO overflowed");
      in_flight_q <= (in_flight_q | (take_read ? Tags'(1) << req_i.tag : '0))
                     & ~(rsp_valid_o && rsp_ready_i ? Tags'(1) << rsp_o.tag : '0);
    end
  end
`endif

endmodule
