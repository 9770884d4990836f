// Included by the netlist testbenches (sim/rpu_*_netlist_tb.sv). open_vectors opens the file
// that a co-simulation harness wrote, named by +vectors=FILE, and reads +seed=N (default
// 1). A missing argument or an unreadable file stops the simulation with a message.
task automatic open_vectors(output reg [1023:0] path, output integer fd, output integer seed);
  if (!$value$plusargs("vectors=%s", path)) begin
    $display("netlist FAIL: no +vectors=FILE");
    $fatal(2);
  end
  if (!$value$plusargs("seed=%d", seed)) seed = 1;
  fd = $fopen(path, "r");
  if (fd == 0) begin
    $display("netlist FAIL: cannot open %0s", path);
    $fatal(2);
  end
endtask

// Four clock cycles in reset, then out of it (the including testbench's clk and rst_n).
task automatic reset_dut;
  repeat (4) begin
    #1 clk = 1'b1;
    #1 clk = 1'b0;
  end
  rst_n = 1'b1;
endtask
