// Formatted against .clang-format on purpose: the format check must catch it.
int   badlyFormatted( int a ){return a+1;}
