#include <CLI/CLI.hpp>
int main(int argc, char** argv) {
  CLI::App app{"skypol: skylight polarization renderer and north-finding benchmark"};
  CLI11_PARSE(app, argc, argv);
  return 0;
}
