// Values written into the batch scripts that `penumbra submit` hands to Slurm: each is checked to
// be one line of text, then quoted for the reader that parses it (the shell, or sbatch's reader of
// `#SBATCH` lines), so that no value from the command line, a scene or a path becomes a command.
#pragma once

#include <string>

namespace penumbra {

// Throws InputError "WHAT: ... contains a control character (a newline, ...)" when `text` holds a
// byte below 0x20 or 0x7f: a newline would end the line it is written on, in a comment, an
// #SBATCH line or a command, and start a line of its own.
void requireOneLineOfText(const std::string& what, const std::string& text);

// `sh -c` quoting: 'text' with every ' written as '\''.
std::string shellQuote(const std::string& text);

// One argument of an `#SBATCH` line as sbatch reads it: the text itself when it is only letters,
// digits and -_=.,:/+@%, else "text" with every " and \ written \" and \\. Unquoted, whitespace would split
// the argument (a backslash does not escape it there) and a
// '#' would end the line as a comment.
std::string sbatchQuote(const std::string& text);

// A path in an sbatch file name pattern (--output): '%' starts a replacement there, so it is
// written '%%', then quoted as sbatchQuote does.
std::string sbatchQuoteFilenamePattern(const std::string& literalPath, const std::string& pattern);

}  // namespace penumbra
