#pragma once
// The frontend's on-chip memories (paper Sec. V-C, Fig. 11), sized from the configured datapath,
// the trace's work (largest per-frame lists, pyramid shapes) and the DES's own cycle numbers:
//
//  stencil buffers (cascaded line FIFOs + shift registers, arch/memory/stencil_buffer.hpp)
//    fe.L<l>   FD (fd_stencil²) and IF (if_stencil²) sharing the pyramid stream of level l, one
//              set time-shared by the left and right images (the Fig. 12 case)
//    fc.L<l>   FC's rBRIEF patch (fc_patch²) on IF's smoothed stream of level l
//    dc.L<l>   DC's Scharr (dc_stencil²) and the 5x5 Gaussian of pyrDown on the LK pyramid
//    dr.left, dr.right   DR's window (and the right image's window plus the search range)
//  FIFOs      FD -> FC keypoints of both images, MO -> DR matches, LSS -> host tracks
//  scratchpad LK pyramids of the previous and the current left image (LSS reads windows at
//             arbitrary positions), previous features, keypoints and descriptors of both images
//             for MO's arbitrary accesses, and, with input_buffering: on_chip_double, the left and
//             right images of two frames (Sec. V-A; neither a stencil nor a queue: the SPM, the
//             paper's third kind of on-chip memory). The two buffered frames are the previous and
//             the current one LSS needs, so their left images are level 0 of the two LK pyramids,
//             which the SPM then does not hold twice.
//
// The SB optimization: DR reads the same level-0 pixels as FD/IF but millions of cycles later.
// Sharing FD/IF's SB would keep each pixel from its read for FD/IF (P1) until DR (C2); reading it
// again just before DR (P2 > C1) needs only DR's own window lines. Decided per image with the rule
// of Sec. V-C on the stream timings of the DES (the frame with the longest lifetimes). The re-read
// comes from the on-chip input buffer (dr_reread: on_chip_frame) or from DRAM (dr_reread: dram,
// or input_buffering: dram), whose bytes are counted.
//
// Without the optimization, the SB DR would share holds each pixel for its lifetime; two sizes
// are reported: the paper's rule (lifetime x producer rate, Sec. V-C and VII-B: "a pixel would
// have to stay in the SB for over 3 million cycles") and the FIFO occupancy bound (a FIFO never
// holds more than the images of the frames in flight: n pixels an image, two frames with FE/SM
// pipelining).
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "arch/frontend/frontend_config.hpp"
#include "arch/frontend/frontend_model.hpp"
#include "arch/memory/bram.hpp"
#include "arch/memory/fifo.hpp"
#include "arch/memory/on_chip_memory.hpp"
#include "arch/memory/scratchpad.hpp"
#include "arch/memory/stencil_buffer.hpp"
#include "workloads/trace/records.hpp"

namespace edx::arch {

struct FrontendMemoryPlan {
  std::vector<StencilBuffer> stencil_buffers;
  std::vector<FifoSizing> fifos;
  ScratchpadSizing scratchpad;
  /// The SB decision for DR's reads of the left and the right image.
  SbSharingDecision dr_left, dr_right;
  bool sb_optimization = true;  ///< config: replicate into DR's own SB when the rule says so
  std::int64_t sb_bytes =
      0;  ///< line FIFOs of every SB (+ the shared lifetime when not replicating)
  /// The same with DR sharing FD/IF's SB, by the paper's rule (lifetime x rate).
  std::int64_t sb_bytes_without_optimization = 0;
  /// The same, by the FIFO occupancy bound (at most the images of the frames in flight).
  std::int64_t sb_bytes_without_optimization_bound = 0;
  std::int64_t fifo_bytes = 0;
  std::int64_t spm_bytes = 0;
  std::int64_t input_buffer_bytes = 0;  ///< of spm_bytes, the input images (0 when in DRAM)
  /// DRAM reads a frame: the input images once (by the DMA, or by FD/IF's streams), DC's stream
  /// of the left image when it is not on chip, and DR's re-reads when they come from DRAM.
  std::int64_t dram_bytes_per_frame = 0;
  std::int64_t extra_dram_bytes_per_frame = 0;  ///< the part of it beyond reading each image once
  BramBudget bram;  ///< every structure, mapped by the memory kind, against the device
  nlohmann::json to_json() const;  ///< also the paper's units: sb_mb, spm_mb, ... (10^6 B)
};

/// Plans the memories for the frames of a trace and their DES timing (`timing`, from
/// simulate_frontend on the same frames and config). `width` x `height`: the image size. The
/// structures are mapped onto `device`'s blocks by the platform's `memory` kind.
FrontendMemoryPlan plan_frontend_memory(const std::vector<trace::FrameTrace>& frames,
                                        const FrontendSimResult& timing, int width, int height,
                                        const FrontendConfig& config, const Device& device,
                                        const OnChipMemory& memory);

}  // namespace edx::arch
