#include "pipeline/ibr_settings.h"

#include "ibr/lumi_net_model.h"
#include "shared/config.h"

namespace rt::pipeline {

using config::KnobKind;

const config::KnobTable<IbrSettings>& ibr_knobs() {
  static const config::KnobTable<IbrSettings> table = {
      {"views", "Cameras used per frame", KnobKind::Integer, 1, 6, {},
       [](const IbrSettings& s) { return double(s.views); }, [](IbrSettings& s, double v) { s.views = uint32_t(v); }},
      {"fusion", "Depth fusion: min (the paper), avg (baseline)", KnobKind::Choice, 0, 0, {"min", "avg"},
       [](const IbrSettings& s) { return s.fusion == passes::DepthFusion::Min ? 0.0 : 1.0; },
       [](IbrSettings& s, double v) { s.fusion = v == 0 ? passes::DepthFusion::Min : passes::DepthFusion::Average; }},
      {"carve",
       "See-through carving: a fused point that a camera looks straight through takes the surface behind "
       "(reopens finger gaps narrower than a depth pixel)",
       KnobKind::Flag, 0, 1, {}, [](const IbrSettings& s) { return s.carve ? 1.0 : 0.0; },
       [](IbrSettings& s, double v) { s.carve = v != 0; }},
      {"refine", "Plane-sweep refinement with this many depth hypotheses (0 = off)", KnobKind::Integer, 0, 64, {},
       [](const IbrSettings& s) { return s.refine ? double(s.refinement.hypotheses) : 0.0; },
       [](IbrSettings& s, double v) {
         s.refine = v > 0;
         if (s.refine) s.refinement.hypotheses = int(v);
       }},
      {"best-views",
       "Blending's k: the k-1 best views blend, the k-th has weight 0 (2 = the best view alone; views + 1 = all of them)",
       KnobKind::Integer, 2, RT_IBR_MAX_VIEWS + 1, {}, [](const IbrSettings& s) { return double(s.blend.best_views); },
       [](IbrSettings& s, double v) { s.blend.best_views = int(v); }},
      {"average-tolerance",
       "avg fusion: depths up to this many metres behind the nearest agree with it and join the mean (large, e.g. 0.1 = "
       "a plain mean that blurs edges)",
       KnobKind::Real, 0, 10, {}, [](const IbrSettings& s) { return double(s.splat.average_tolerance_m); },
       [](IbrSettings& s, double v) { s.splat.average_tolerance_m = float(v); }},
      {"edge-inset",
       "Splat sides on outlines and depth edges pulled in by this much of a depth pixel (0.3 gains with --views 6 and "
       "--portrait-supersample 3; loses with four views)",
       KnobKind::Real, 0, 0.49, {}, [](const IbrSettings& s) { return double(s.splat.edge_inset); },
       [](IbrSettings& s, double v) { s.splat.edge_inset = float(v); }},
      {"portrait-supersample", "Portrait rendered at N x N samples per pixel and resolved (partial alpha on edges)",
       KnobKind::Integer, 1, 4, {}, [](const IbrSettings& s) { return double(s.supersample); },
       [](IbrSettings& s, double v) { s.supersample = uint32_t(v); }},
      {"fill-holes",
       "Fill the portrait's enclosed holes: an uncovered pixel with a covered one within this many pixels on all four "
       "sides of its row and column takes their inverse-distance mean (0 = off)",
       KnobKind::Integer, 0, 64, {}, [](const IbrSettings& s) { return double(s.fill_holes_px); },
       [](IbrSettings& s, double v) { s.fill_holes_px = uint32_t(v); }},
      {"blend", "Blending of the warped views: ulr (unstructured lumigraph weights), lumi (Lumi-Net, learned weights and alpha)",
       KnobKind::Choice, 0, 0, {"ulr", "lumi"},
       [](const IbrSettings& s) { return s.blending == IbrBlending::Ulr ? 0.0 : 1.0; },
       [](IbrSettings& s, double v) { s.blending = v == 0 ? IbrBlending::Ulr : IbrBlending::Lumi; }},
      {"split-warp",
       "Warp each view into its own image, then blend (the per-view images a window's F2 and F3 show); "
       "lumigraph blending otherwise warps and blends in one pass, Lumi-Net always splits",
       KnobKind::Flag, 0, 1, {}, [](const IbrSettings& s) { return s.split_warp ? 1.0 : 0.0; },
       [](IbrSettings& s, double v) { s.split_warp = v != 0; }},
      {"lumi-weights", "--blend lumi: the network's weights file (scripts/train-lumi writes it)", KnobKind::Text, 0, 0, {},
       {}, {}, [](const IbrSettings& s) { return lumi_weights_path(s).string(); },
       [](IbrSettings& s, const std::string& path) { s.lumi_weights = path; }},
  };
  return table;
}

bool splits_warp(const IbrSettings& settings) { return settings.split_warp || settings.blending == IbrBlending::Lumi; }

const char* blending_name(IbrBlending blending) { return blending == IbrBlending::Lumi ? "lumi" : "ulr"; }

std::filesystem::path lumi_weights_path(const IbrSettings& settings) {
  return settings.lumi_weights.empty() ? ibr::default_lumi_net_path() : settings.lumi_weights;
}

nlohmann::json ibr_settings_json(const IbrSettings& settings) { return config::knobs_to_json(ibr_knobs(), settings); }

}  // namespace rt::pipeline
