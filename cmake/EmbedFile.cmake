# cmake -DINPUT=<file> -DOUTPUT=<cpp> -DSYMBOL=<name> -P EmbedFile.cmake
file(READ ${INPUT} hex HEX)
string(LENGTH "${hex}" hex_len)
math(EXPR size "${hex_len} / 2")
string(REGEX REPLACE "([0-9a-f][0-9a-f])" "'\\\\x\\1'," bytes "${hex}")
file(WRITE ${OUTPUT}
  "// Generated from ${INPUT} by cmake/EmbedFile.cmake; do not edit.\n"
  "#include <string_view>\n"
  "namespace trainsim::embedded {\n"
  "namespace {\nconstexpr char kData[] = {${bytes} '\\0'};\n}\n"
  "extern const std::string_view ${SYMBOL}(kData, ${size});\n"
  "}  // namespace trainsim::embedded\n")
