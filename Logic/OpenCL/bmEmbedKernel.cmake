# bmEmbedKernel.cmake - cmake -DIN=x.cl -DOUT=x.cxx -DNAME=stem -P bmEmbedKernel.cmake
# Writes a C++ file defining bm::kernels::<NAME> (the .cl text, declared in bmKernelSources.h).
# The text goes out in raw-string pieces of at most 8000 characters (compiler literal limits).
file(READ ${IN} text)
string(LENGTH "${text}" len)
set(body "")
set(pos 0)
while(pos LESS len)
  string(SUBSTRING "${text}" ${pos} 8000 piece)
  string(APPEND body "R\"bmcl(${piece})bmcl\"\n")
  math(EXPR pos "${pos} + 8000")
endwhile()
file(WRITE ${OUT} "// Generated from ${IN} by bmEmbedKernel.cmake; do not edit.\n"
     "#include \"bmKernelSources.h\"\nnamespace bm::kernels {\nconst char* const ${NAME} =\n${body};\n}\n")
