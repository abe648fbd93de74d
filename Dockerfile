# softpbr in a container: Debian 12, built, tested and installed by the quick-start script,
# `softpbr` as the entry point (docs/cli.md, "Many frames on many machines").
#
#   docker build -t softpbr:0.1 .
#   docker run --rm -v "$PWD:/data" -w /data softpbr:0.1 render scene.json -o scene.png
#   docker run --rm --entrypoint python3 softpbr:0.1 -c "import softpbr"   # the Python module too
#
# The steps are the README's: ./scripts/test as root installs the Debian packages of
# scripts/setup.sh with apt-get, builds build/ (Release) and runs the whole test suite, so
# CI's run of ./scripts/test covers them; then `cmake --install` into /usr/local (the command,
# the libraries, the CMake and pkg-config packages, the Python package for /usr/bin/python3).
# cmake/TestDockerfile.cmake (ctest dockerfile_steps) checks that these steps stay so.
FROM debian:12

WORKDIR /src
COPY . /src
RUN ./scripts/test \
 && cmake --install build --prefix /usr/local \
 && rm -rf build /var/lib/apt/lists/*

WORKDIR /data
ENTRYPOINT ["softpbr"]
CMD ["--help"]
