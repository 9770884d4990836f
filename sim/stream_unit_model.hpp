#pragma once

// A unit with one request stream in and one response stream out (valid/ready each), as
// the co-simulation tops of the FP units (rpu_fp_cosim_top.sv) and the intersection
// unit (rpu_iu_cosim_top.sv) have it: the interface the harnesses drive, free of any
// Verilator header, so the models are built in their own library with Verilator's
// flags rather than the project's warnings.
namespace rpu::sim {

template <class Req, class Rsp>
struct StreamUnitInputs {
  bool rst_n = false;
  bool req_valid = false;
  Req req;
  bool rsp_ready = false;
};

template <class Rsp>
struct StreamUnitOutputs {
  bool req_ready = false;
  bool rsp_valid = false;
  Rsp rsp;
};

template <class Req, class Rsp>
class StreamUnitModel {
 public:
  using Inputs = StreamUnitInputs<Req, Rsp>;
  using Outputs = StreamUnitOutputs<Rsp>;
  virtual ~StreamUnitModel() = default;
  // Applies the inputs with the clock low and returns the outputs they give.
  virtual Outputs settle(const Inputs& in) = 0;
  // One rising and one falling clock edge.
  virtual void clock() = 0;
  // Closes the waveforms and renames them over their path; rpu::Error naming it if they
  // could not be written. Without waveforms, nothing.
  virtual void close_trace() = 0;
};

}  // namespace rpu::sim
