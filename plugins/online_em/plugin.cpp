// ABI shim: the online EM SLAM core as plugin "online_em".
#include "online_em_config.hpp"
#include "online_em_slam.hpp"
#include "roam/plugin_shim.hpp"

namespace {

std::unique_ptr<roam::Estimator> makeOnlineEm(roam::Options& options) {
  roam::online_em::OnlineEmConfig config;
  roam::online_em::addOnlineEmOptions(options, &config);
  options.parse();
  return std::make_unique<roam::online_em::OnlineEmSlam>(config);
}

}  // namespace

ROAM_DEFINE_PLUGIN("online_em", "Le Corff, Fort & Moulines 2011 online EM SLAM (particles + EM map)",
                   makeOnlineEm)
