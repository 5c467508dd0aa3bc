# Turn a text file into a C string literal: -DIN=file -DOUT=file.c -DNAME=symbol
file(READ "${IN}" text)
string(REPLACE "\\" "\\\\" text "${text}")
string(REPLACE "\"" "\\\"" text "${text}")
string(REPLACE "\n" "\\n\"\n\"" text "${text}")
file(WRITE "${OUT}" "/* generated from ${IN}; do not edit */\n#include \"vibroimpact/vi_export.h\"\nVI_API const char *${NAME}(void);\nconst char *${NAME}(void)\n{\n  return \"${text}\";\n}\n")
