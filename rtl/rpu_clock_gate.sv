// A clock gate (the integrated clock-gating cell of a standard-cell library): clk_o
// pulses with clk_i in the cycles en_i was high while clk_i was low before the edge.
// The latch holds the enable through the high phase, so clk_o has no glitch however
// en_i moves then. A gated unit's registers hold their values in the cycles it is off,
// as registers whose every enable is low would; Verilator evaluates a unit's logic
// only on the edges of its own clock, so an idle unit costs the simulation nothing
// (docs/rtl.md "Clock gates").
//
// en_i must be settled while the clock is low: the co-simulation harnesses apply the
// top's inputs with the clock low and evaluate before each rising edge (settle() in
// sim/cosim_core.hpp), so an enable may depend on them too.
module rpu_clock_gate (
  input  logic clk_i,
  input  logic en_i,
  output logic clk_o
);

  logic en_q;

  always_latch begin : en_latch
    if (!clk_i) en_q = en_i;
  end

  assign clk_o = clk_i & en_q;

endmodule
