# Sourced by bench/vs-liggghts and bench/vs-liggghts-clumps: installs LIGGGHTS 3.8 (Debian's
# `liggghts`) if it is missing, and sets mpi_root, the mpirun flag a root user needs.
if ! command -v liggghts >/dev/null; then
  sudo_cmd=()
  if [[ $(id -u) -ne 0 ]]; then sudo_cmd=(sudo); fi
  "${sudo_cmd[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y -q liggghts
fi
mpi_root=()
if [[ $(id -u) -eq 0 ]]; then mpi_root=(--allow-run-as-root); fi
