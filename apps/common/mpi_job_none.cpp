// apps::MpiJob in a build without MPI: every process is a job of one (see mpi_job.h).
#include "mpi_job.h"

#include <librt/core/error.h>

namespace librt::apps {

MpiJob::MpiJob(int& /*argc*/, char**& /*argv*/) {}

MpiJob::~MpiJob() = default;

int MpiJob::run(const std::function<int()>& body) const { return body(); }

void MpiJob::setup_succeeded() const {}

void MpiJob::check_same_job(
    const std::vector<std::pair<std::string, std::string>>& /*items*/) const {}

void MpiJob::check_all_ranks(const std::string& local_error) const {
    if (!local_error.empty()) throw Error(local_error);
}

Film MpiJob::render(const Scene& /*scene*/, const Camera& /*camera*/, Integrator& /*integrator*/,
                    const MpiJobSettings& /*settings*/, MpiJobStats& /*stats*/,
                    Image& /*image*/) const {
    throw Error("MpiJob::render: this rt_render was built without MPI");
}

}  // namespace librt::apps
