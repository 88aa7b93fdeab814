#include <iostream>
#include <string>
#include <vector>

#include "cwe/app/cli.hpp"

int main(int argc, char** argv) {
  return cwe::app::run(std::vector<std::string>(argv, argv + argc), std::cout, std::cerr);
}
