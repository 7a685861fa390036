#include "app/mpi_launch.h"

#include <cstdlib>
#include <initializer_list>

namespace ray {

bool launchedByMpirun() {
    for (const char* variable : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK"})
        if (const char* value = std::getenv(variable); value && *value) return true;
    return false;
}

int launcherRank() {
    for (const char* variable : {"OMPI_COMM_WORLD_RANK", "PMIX_RANK", "PMI_RANK"})
        if (const char* value = std::getenv(variable); value && *value) return std::atoi(value);
    return -1;
}

}  // namespace ray
