// Whether a shader's access of `bytes` at `addr` may happen (docs/shader-core.md
// "Memory"; the functional model's DeviceMemory::check): 4-byte aligned, inside one
// segment (image, launch block, data, framebuffer) from its first to its last byte, a
// framebuffer access inside the thread's own pixel, a store nowhere else. The stack
// segment is reached only by push and pop, never by an address. Combinational; the
// host makes the fault's message from the address (the fault stream carries it).
module rpu_spu_memcheck (
  input  logic [31:0]          addr_i,
  input  logic [4:0]           bytes_i,   // 4 or 16
  input  logic                 write_i,
  input  logic [31:0]          pixel_i,   // the thread's pixel, y * width + x
  input  rpu_pkg::launch_t     launch_i,
  output logic                 ok_o
);

  // 33-bit ends, so that a segment or an access reaching 2^32 compares right.
  logic [32:0] end_addr;
  assign end_addr = {1'b0, addr_i} + 33'(bytes_i);

  // The segment that holds the first byte, and whether the last one is in it too.
  function automatic logic [1:0] segment_hit(input logic [31:0] a, input logic [32:0] e, input logic [31:0] base,
                                        input logic [31:0] size);
    segment_hit = {a >= base && {1'b0, a} < {1'b0, base} + {1'b0, size}, e <= {1'b0, base} + {1'b0, size}};
  endfunction

  logic [1:0] in_image, in_launch, in_data, in_fb;
  logic [31:0] fb_bytes;
  assign fb_bytes  = launch_i.pixels << 4;  // FramebufferBytesPerPixel = 16
  assign in_image  = segment_hit(addr_i, end_addr, rpu_pkg::DeviceImageBase, launch_i.image_bytes);
  assign in_launch = segment_hit(addr_i, end_addr, rpu_pkg::DeviceLaunchBase, launch_i.launch_bytes);
  assign in_data   = segment_hit(addr_i, end_addr, rpu_pkg::DeviceDataBase, launch_i.data_bytes);
  assign in_fb     = segment_hit(addr_i, end_addr, rpu_pkg::DeviceFramebufferBase, fb_bytes);

  // The thread's own 16 bytes of the framebuffer.
  logic [32:0] own_lo, own_hi;
  assign own_lo = {1'b0, rpu_pkg::DeviceFramebufferBase} + {1'b0, pixel_i[27:0], 4'b0000};
  assign own_hi = own_lo + 33'(rpu_pkg::FramebufferBytesPerPixel);

  always_comb begin : access_ok
    if (addr_i[1:0] != 2'b00) begin
      ok_o = 1'b0;
    end else if (in_fb[1]) begin
      ok_o = in_fb[0] && {1'b0, addr_i} >= own_lo && end_addr <= own_hi;
    end else if (in_image[1] || in_launch[1] || in_data[1]) begin
      ok_o = !write_i && (in_image[1] ? in_image[0] : in_launch[1] ? in_launch[0] : in_data[0]);
    end else begin
      ok_o = 1'b0;
    end
  end

  // Only the sizes and the pixel count of the launch matter here.
  logic unused;
  assign unused = ^{launch_i.width, launch_i.height, launch_i.spp, launch_i.max_depth, launch_i.raygen,
                    launch_i.code_words, launch_i.shader_count, launch_i.shader_table, launch_i.watchdog,
                    launch_i.div_magic, launch_i.div_shift1, launch_i.div_shift2, pixel_i[31:28]};

endmodule
