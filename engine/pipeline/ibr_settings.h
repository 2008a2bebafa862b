#pragma once
// What the image-based model (pipeline/ibr_renderer.h) is set to, and its user-settable knobs:
// one table (config/knobs.h) that binds the command-line options of every command that renders
// with it, reads a site config's "ibr" object and forwards the options to a child process. A new
// knob is one field here plus one row in ibr_knobs() (ibr_settings.cpp).
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "config/knobs.h"
#include "passes/ibr_blend.h"
#include "passes/ibr_carve.h"
#include "passes/ibr_foreground.h"
#include "passes/ibr_fuse.h"
#include "passes/ibr_refine.h"
#include "passes/ibr_splat.h"
#include "passes/ibr_warp.h"

namespace rt::pipeline {

// How the warped views become the portrait: unstructured lumigraph weights (passes/ibr_blend.h)
// or Lumi-Net's learned weights and alpha (pipeline/lumi_net.h).
enum class IbrBlending { Ulr, Lumi };

struct IbrSettings {
  uint32_t width = 640, height = 360;  // the target view
  uint32_t views = 4;                  // cameras used per frame (the paper: 4 of 6)
  // The portrait rendered at this many times the target's resolution per axis and resolved
  // (ibr_resolve): partial alpha on silhouettes, texture filtered over each pixel; 1 = off.
  // The splats' largest footprint scales with it.
  uint32_t supersample = 1;
  // The portrait's enclosed holes filled (ibr_fill) where a covered pixel lies within this many
  // pixels on each side along the row and the column; 0 = off. On by default: it is more accurate
  // on every evaluation scene, in eval ibr and in eval dual, at a small share of the model's time.
  uint32_t fill_holes_px = 8;
  passes::DepthFusion fusion = passes::DepthFusion::Min;
  bool carve = false;   // see-through carving of the fused depth, off by default
  bool refine = false;  // plane sweep, off by default
  passes::ForegroundSettings foreground;
  passes::SplatSettings splat;  // its `fusion` is set from `fusion`
  passes::FuseSettings fuse;    // likewise
  passes::CarveSettings carving;
  passes::RefineSettings refinement;
  passes::WarpSettings warp;
  passes::BlendSettings blend;
  IbrBlending blending = IbrBlending::Ulr;
  // Warp every view into its own image first, then blend (ibr_warp, then ibr_blend or Lumi-Net):
  // the per-view images that export lumi and a window's F2 and F3 read. Lumi-Net always splits;
  // lumigraph blending otherwise warps and blends in one pass (ibr_warp_blend).
  bool split_warp = false;
  std::filesystem::path lumi_weights;  // Lumi-Net's weights file; empty: the committed one
};

// Whether the model warps every view into its own image before blending: asked for, or Lumi-Net.
bool splits_warp(const IbrSettings& settings);

// "ulr" or "lumi", as metrics name the blend that ran.
const char* blending_name(IbrBlending blending);
// settings.lumi_weights, or the committed weights (ibr::default_lumi_net_path()) when empty.
std::filesystem::path lumi_weights_path(const IbrSettings& settings);

// views, fusion, carve, refine, best-views, average-tolerance, edge-inset, portrait-supersample,
// fill-holes, blend, split-warp, lumi-weights.
const config::KnobTable<IbrSettings>& ibr_knobs();

// Every knob of `settings` as JSON (keys as in a site config's "ibr" object), for metrics files.
nlohmann::json ibr_settings_json(const IbrSettings& settings);

}  // namespace rt::pipeline
