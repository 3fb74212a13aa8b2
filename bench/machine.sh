# Sourced by the bench scripts: `machine` prints the line that heads each results CSV's
# first line, the machine the numbers were measured on (cores and processor model).
machine() {
  echo "$(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')"
}
