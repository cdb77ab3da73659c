using PmacStream.GCode;

namespace PmacStream.Preparation;

/// <content>The writing side of a split: the batches from the reading side, line by line, through the line writer into the packer.</content>
public static partial class Splitter
{
    /// <content>The writing side of a split: each batch's lines written (<see cref="ChunkLineWriter"/>) into the chunk being packed (<see cref="ChunkPacker"/>).</content>
    private sealed partial class SplitRun
    {
        /// <summary>The splitting thread's work on one batch.</summary>
        private void Consume(LineBatch batch)
        {
            var text = batch.Text;
            var lines = batch.Lines;
            var n = 0;
            while (n < lines.Length)
            {
                ref readonly var line = ref lines[n];
                if ((n & 0x3FF) == 0x3FF)
                {
                    _ct.ThrowIfCancellationRequested();
                }

                if (line.IsAxisLine)
                {
                    EmitAxisLine(text.AsSpan(line.TextStart, line.TextLength), line.WordCount, line.LineNumber);
                    n++;
                }
                else if (n + 1 < lines.Length && lines[n + 1].Continues)
                {
                    // A host block of several lines: emitted together (they stay in one chunk).
                    n = EmitGroup(batch, n);
                }
                else
                {
                    Emit(text.AsSpan(line.TextStart, line.TextLength), batch.WordsOf(line), line.LineNumber);
                    n++;
                }
            }

            _packer.Position = batch.EndPosition;
        }

        /// <summary>The last chunk, once the reading side finished: unless what it found refuses the split.</summary>
        private void Finish(ReadOutcome read)
        {
            if (Checking && !_o.AllowErrors && read.CheckErrorCount > 0)
            {
                throw new SplitException(
                    $"{_source}: {read.CheckErrorCount} error(s); not split (force splits anyway)", read.CheckErrors, read.CheckErrorCount)
                {
                    FromChecker = true,
                };
            }

            // Also when checking: lines stopped flowing at the first lexical error, so never publish what came before.
            if (read.ErrorCount > 0 && !_o.AllowErrors)
            {
                throw new SplitException(
                    $"{_source}: {read.ErrorCount} error(s); not split (force splits anyway, dropping what is not G-code)",
                    read.Errors, read.ErrorCount);
            }

            if (_packer.Empty)
            {
                throw new SplitException($"{_source}: no program blocks to split", [], 1);
            }

            _packer.Close();
        }

        /// <summary>The lines of one host block from <paramref name="first"/> on, as one block of the chunk; returns the index after them.</summary>
        private int EmitGroup(LineBatch batch, int first)
        {
            var lines = batch.Lines;
            var end = first + 1;
            var room = 0;
            while (end < lines.Length && lines[end].Continues)
            {
                end++;
            }

            for (var i = first; i < end; i++)
            {
                room += _lines.Room(lines[i].TextLength, lines[i].WordCount);
            }

            var space = _packer.Reserve(room);
            var o = space;
            var moves = 0;
            var endsProgram = false;
            var words = 0;
            for (var i = first; i < end; i++)
            {
                var written = _lines.Write(o, batch.Text.AsSpan(lines[i].TextStart, lines[i].TextLength), batch.WordsOf(lines[i]), lines[i].LineNumber,
                    out var motion, out var ends, out var values);
                if (written == 0)
                {
                    continue;
                }

                o = o[written..];
                moves |= motion != BlockMotion.None ? 1 : 0; // one source block, however many moves the host made of it
                endsProgram |= ends;
                words += Math.Max(_wordsPerBlock, values);
            }

            if (space.Length != o.Length)
            {
                _packer.Add(space.Length - o.Length, lines[first].LineNumber, moves, endsProgram, words);
            }

            return end;
        }

        private void Emit(ReadOnlySpan<byte> src, ReadOnlySpan<GWord> words, int lineNumber)
        {
            var space = _packer.Reserve(_lines.Room(src.Length, words.Length));
            var written = _lines.Write(space, src, words, lineNumber, out var motion, out var endsProgram, out var values);
            if (written > 0)
            {
                _packer.Add(written, lineNumber, motion != BlockMotion.None ? 1 : 0, endsProgram, Math.Max(_o.WordsPerBlock, values));
            }
        }

        /// <summary>An <see cref="AxisLine"/>: a move of the words as emitted, markers around them.</summary>
        private void EmitAxisLine(ReadOnlySpan<byte> text, int words, int lineNumber)
        {
            var written = _lines.WriteAxisLine(_packer.Reserve(_lines.AxisRoom(text.Length)), text, words, lineNumber, out var values);
            _packer.Add(written, lineNumber, motions: 1, endsProgram: false, Math.Max(_wordsPerBlock, values));
        }
    }
}
