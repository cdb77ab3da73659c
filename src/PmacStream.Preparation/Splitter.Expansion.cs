using System.Text;
using PmacStream.GCode;
using PmacStream.GCode.Expansion;

namespace PmacStream.Preparation;

/// <content>
/// A program with subprograms, macros or o-words is split from its expansion: the chunks carry the expanded blocks,
/// <c>M0==</c> counts expanded lines, and <see cref="ExpansionMap.FileName"/> beside the manifest maps each back to
/// its file, line, calls and iteration. A program without them is split from its file, exactly as before.
/// </content>
public static partial class Splitter
{
    /// <content>The expansion's side of the reading side of a split.</content>
    private sealed partial class SourceReader
    {
        private MacroExpander? _expander;
        private Diagnostic? _expansionError; // the expansion's refusal, for an import in the same pass
        private StreamWriter? _mapWriter;

        /// <summary>The program text to split: the file, or its expansion (writing the map beside the chunks).</summary>
        private Stream OpenSource()
        {
            if (_o.CheckProfile is { } profile && ProgramExpansion.Applies(_source, profile))
            {
                var map = new ExpansionMap(1 << 16);
                _mapWriter = new StreamWriter(Path.Combine(_folder, ExpansionMap.FileName), false, new UTF8Encoding(false), 1 << 16);
                map.WriteTo(_mapWriter);
                _expander = new MacroExpander(_source, ProgramExpansion.For(profile, _o.Expansion), map);
                return new ExpandedStream(_expander);
            }

            var file = new FileStream(_source, FileMode.Open, FileAccess.Read, FileShare.Read, 1, FileOptions.SequentialScan);
            if (_import == null)
            {
                return file;
            }

            // An import in the same pass: the SHA-256 and the stored source bytes come from this one read.
            _file = file;
            return _hashing = new Store.HashingReadStream(file, _import.Revision.Pieces);
        }

        /// <summary>The bytes of the source read (the file's size when it was expanded: the manifest's size is the file's).</summary>
        private long SourceRead(GCodeReader reader) => _expander != null ? _totalBytes : reader.Position;

        /// <summary>The expansion ended: its refusal refuses the split; the map is complete; the machine's persistent variables are kept.</summary>
        private void EndExpansion()
        {
            if (_expander == null)
            {
                return;
            }

            if (_expander.Error is { } e)
            {
                _expansionError = ProgramExpansion.ToDiagnostic(e, _source);
                OnCheckDiagnostic(_expansionError);
            }
            else
            {
                _expander.SavePersistentVariables();
            }

            _mapWriter?.Dispose();
            _mapWriter = null;
        }

        /// <summary>A diagnostic of an expanded line, on its source line.</summary>
        private Diagnostic FromExpansion(Diagnostic d) => _expander == null ? d : ProgramExpansion.ToSource(d, _expander.Map);
    }
}
