using System.Runtime.CompilerServices;
using System.Runtime.InteropServices;
using PmacStream.GCode;

namespace PmacStream.Preparation;

/// <content>The writing side of a split: chunk lines written byte by byte (tracking assignments, feed variable, stops), chunk files flushed.</content>
public static partial class Splitter
{
    /// <content>The writing side of a split: chunk lines written byte by byte (tracking assignments, feed variable, stops), chunk files flushed.</content>
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

            _position = batch.EndPosition;
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

            if (_chunkBlocks == 0)
            {
                throw new SplitException($"{_source}: no program blocks to split", [], 1);
            }

            Flush(last: true);
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
                room += (2 * lines[i].TextLength) + (2 * lines[i].WordCount) + 64 + (2 * (_trackPrefix.Length + _feedSuffix.Length));
            }

            var space = _chunk.Reserve(room);
            var o = space;
            var moves = 0;
            var endsProgram = false;
            var words = 0;
            for (var i = first; i < end; i++)
            {
                var written = Write(o, batch.Text.AsSpan(lines[i].TextStart, lines[i].TextLength), batch.WordsOf(lines[i]), lines[i].LineNumber,
                    out var motion, out var ends, out var values);
                if (written == 0)
                {
                    continue;
                }

                o = o[written..];
                moves |= motion != BlockMotion.None ? 1 : 0; // one source block, however many moves the host made of it
                endsProgram |= ends;
                words += Math.Max(_o.WordsPerBlock, values);
            }

            if (space.Length != o.Length)
            {
                Add(space.Length - o.Length, lines[first].LineNumber, moves, endsProgram, words);
            }

            return end;
        }

        private void Emit(ReadOnlySpan<byte> src, ReadOnlySpan<GWord> words, int lineNumber)
        {
            var space = _chunk.Reserve((2 * src.Length) + (2 * words.Length) + 64 + (2 * (_trackPrefix.Length + _feedSuffix.Length)));
            var written = Write(space, src, words, lineNumber, out var motion, out var endsProgram, out var values);
            if (written > 0)
            {
                Add(written, lineNumber, motion != BlockMotion.None ? 1 : 0, endsProgram, Math.Max(_o.WordsPerBlock, values));
            }
        }

        /// <summary>Writes one block's chunk text at <paramref name="space"/>; returns its length (0: nothing for the controller).</summary>
        private int Write(Span<byte> space, ReadOnlySpan<byte> src, ReadOnlySpan<GWord> words, int lineNumber, out BlockMotion motion, out bool endsProgram, out int values)
        {
            // Hot path: spans over the batch's word list and line bytes, written straight into the chunk being
            // built; no allocation and no intermediate copy per block.
            var paperFeed = _o.Feed == FeedMode.Paper;
            var feedIndex = -1;
            var nIndex = -1;
            var any = false;
            var scan = default(MotionScan);
            for (var i = 0; i < words.Length; i++)
            {
                switch (words[i].Letter)
                {
                    case 'N':
                        nIndex = nIndex < 0 ? i : nIndex;
                        break;
                    case 'O':
                        break;
                    case 'F' when paperFeed:
                        feedIndex = i;
                        break;
                    default:
                        any = true;
                        scan.Add(words[i], _stops);
                        break;
                }
            }

            if (feedIndex >= 0 && words[feedIndex].Value.Equals(_feedSet))
            {
                // The feed variable already holds this feed: a P500= line would only repeat it.
                feedIndex = -1;
            }

            motion = scan.Result;
            if (motion == BlockMotion.None && scan.ToolChange && _toolChangeMoves)
            {
                // The tool change hook moves the machine: tracked like a dwell (its marker, no feed suffix).
                motion = BlockMotion.Dwell;
            }

            endsProgram = scan.EndsProgram && motion == BlockMotion.None;
            values = 0;
            if (!any && feedIndex < 0)
            {
                return 0; // empty, comment-only, N-only, O-only or an unchanged F: nothing for the controller
            }

            // The room (reserved by the caller) is an upper bound: every word's text plus a separator, the source line
            // once more (for P500=F), markers.
            var o = space;
            if (feedIndex >= 0)
            {
                // Where the program changes F, the value goes into the feed variable so F(P500) keeps it.
                _feedSet = words[feedIndex].Value;
                o = Put(o, _feedVar);
                o[0] = (byte)'=';
                o = Number(o[1..], src, words[feedIndex]);
                o[0] = (byte)'\r';
                o[1] = (byte)'\n';
                o = o[2..];
                values++;
            }

            if (any)
            {
                var sep = false;
                if (_o.KeepN && nIndex >= 0)
                {
                    o[0] = (byte)'N';
                    o = Number(o[1..], src, words[nIndex]);
                    sep = true;
                    values++;
                }

                var tracked = motion != BlockMotion.None;
                if (tracked && _exactTracking)
                {
                    if (sep)
                    {
                        o[0] = (byte)' ';
                        o = o[1..];
                    }

                    o = Track(o, lineNumber);
                    sep = true;
                    values++;
                }

                if (motion == BlockMotion.Stop)
                {
                    // The dwell ends lookahead and carries the marker: M0 names the stop's line while the controller
                    // waits there, whatever the stop code's routine does.
                    _stopCodes.TryAdd(scan.StopCode!, lineNumber);
                    if (sep)
                    {
                        o[0] = (byte)' ';
                        o = o[1..];
                    }

                    o = Put(o, DwellZero);
                    sep = true;
                    values++;
                }

                // A block's G codes apply to its move wherever the program writes them (X1 G00 is a rapid), but on the
                // controller a G code is a library call that runs where it stands: written after the axis words it would
                // change the mode only from the next move. So the G codes go first; a block that writes them first (all
                // the usual ones) is written as it is.
                var gFirst = false;
                var other = false;
                foreach (ref readonly var w in words)
                {
                    if (w.Letter == 'G')
                    {
                        gFirst |= other;
                    }
                    else if (w.Letter is not ('N' or 'O'))
                    {
                        other = true;
                    }
                }

                for (var pass = gFirst ? 0 : 1; pass < 2; pass++)
                {
                    foreach (ref readonly var w in words)
                    {
                        if (w.Letter is 'N' or 'O' || (w.Letter == 'F' && paperFeed) || (gFirst && (w.Letter == 'G') != (pass == 0)))
                        {
                            continue;
                        }

                        if (sep)
                        {
                            o[0] = (byte)' ';
                            o = o[1..];
                        }

                        o[0] = (byte)w.Letter;
                        o = Number(o[1..], src, w);
                        sep = true;
                        values++;
                    }
                }

                if (motion == BlockMotion.Move && paperFeed)
                {
                    o = Put(o, _feedSuffix, _feedSuffixWord); // " F(P500)"
                    values++;
                }

                if (tracked && !_exactTracking)
                {
                    o[0] = (byte)' ';
                    o = Track(o[1..], lineNumber);
                    values++;
                }

                o[0] = (byte)'\r';
                o[1] = (byte)'\n';
                o = o[2..];
            }

            return space.Length - o.Length;
        }

        /// <summary>
        /// <see cref="Emit"/> for an <see cref="AxisLine"/>: its text is already the words as emitted, so only the
        /// markers go around it. A move, so it is tracked and (paper feed) gets the feed suffix.
        /// </summary>
        private void EmitAxisLine(ReadOnlySpan<byte> text, int words, int lineNumber)
        {
            // The same bytes as Emit, written through one reference into the reserved space instead of span slices
            // (this runs for nearly every line): the room covers the markers' 8- and 16-byte stores.
            var space = _chunk.Reserve(text.Length + 64 + (2 * (_trackPrefix.Length + _feedSuffix.Length)));
            ref var o = ref MemoryMarshal.GetReference(space);
            var at = 0;
            var values = words + 1;
            if (_exactTracking)
            {
                at = TrackAt(ref o, lineNumber);
                Unsafe.Add(ref o, at++) = (byte)' ';
            }

            text.CopyTo(MemoryMarshal.CreateSpan(ref Unsafe.Add(ref o, at), text.Length));
            at += text.Length;
            if (_paperFeed)
            {
                at += PutAt(ref Unsafe.Add(ref o, at), _feedSuffix, _feedSuffixWord); // " F(P500)"
                values++;
            }

            if (!_exactTracking)
            {
                Unsafe.Add(ref o, at++) = (byte)' ';
                at += TrackAt(ref Unsafe.Add(ref o, at), lineNumber);
            }

            Unsafe.WriteUnaligned(ref Unsafe.Add(ref o, at), (ushort)('\r' | ('\n' << 8)));
            Add(at + 2, lineNumber, motions: 1, endsProgram: false, Math.Max(_wordsPerBlock, values));
        }

        /// <summary>Writes a fixed marker at <paramref name="o"/> (one 8-byte store when it fits in 8); returns its length.</summary>
        [System.Runtime.CompilerServices.MethodImpl(System.Runtime.CompilerServices.MethodImplOptions.AggressiveInlining)]
        private static int PutAt(ref byte o, byte[] bytes, ulong word)
        {
            if (bytes.Length <= 8)
            {
                Unsafe.WriteUnaligned(ref o, word);
            }
            else
            {
                bytes.CopyTo(MemoryMarshal.CreateSpan(ref o, bytes.Length));
            }

            return bytes.Length;
        }

        /// <summary>Writes <c>M0==</c> and the line's digits at <paramref name="o"/> (16 bytes of room after the marker); returns the length.</summary>
        [System.Runtime.CompilerServices.MethodImpl(System.Runtime.CompilerServices.MethodImplOptions.AggressiveInlining)]
        private int TrackAt(ref byte o, int sourceLine)
        {
            var at = PutAt(ref o, _trackPrefix, _trackPrefixWord);
            return at + _trackDigits.Write(MemoryMarshal.CreateSpan(ref Unsafe.Add(ref o, at), 16), sourceLine);
        }

        private static Span<byte> Put(Span<byte> o, byte[] bytes)
        {
            bytes.CopyTo(o);
            return o[bytes.Length..];
        }

        /// <summary>
        /// Writes a fixed marker of at most 8 bytes (<paramref name="word"/> holds it, zero-padded) with one 8-byte
        /// store; longer markers, or too little room, take the general copy.
        /// </summary>
        [System.Runtime.CompilerServices.MethodImpl(System.Runtime.CompilerServices.MethodImplOptions.AggressiveInlining)]
        private static Span<byte> Put(Span<byte> o, byte[] bytes, ulong word)
        {
            if (bytes.Length <= 8 && o.Length >= 8)
            {
                MemoryMarshal.Write(o, word);
            }
            else
            {
                bytes.CopyTo(o);
            }

            return o[bytes.Length..];
        }

        private static ulong Word8(byte[] bytes)
        {
            Span<byte> padded = stackalloc byte[8];
            padded.Clear();
            bytes.AsSpan(0, Math.Min(8, bytes.Length)).CopyTo(padded);
            return MemoryMarshal.Read<ulong>(padded);
        }

        /// <summary>A number as written in the source, minus a leading <c>+</c> (the PMAC reads it as an operator).</summary>
        [System.Runtime.CompilerServices.MethodImpl(System.Runtime.CompilerServices.MethodImplOptions.AggressiveInlining)]
        private static Span<byte> Number(Span<byte> o, ReadOnlySpan<byte> src, in GWord w)
        {
            var text = src.Slice(w.NumberStart, w.NumberLength);
            if (text.Length > 1 && text[0] == (byte)'+')
            {
                text = text[1..];
            }

            // Most numbers are under 8 bytes and more line follows them: one 8-byte load and store (the bytes past the
            // number land in reserved space and are overwritten next) instead of a general copy per word.
            var start = w.NumberStart + (w.NumberLength - text.Length);
            if (text.Length <= 8 && src.Length - start >= 8 && o.Length >= 8)
            {
                MemoryMarshal.Write(o, MemoryMarshal.Read<ulong>(src[start..]));
            }
            else
            {
                text.CopyTo(o);
            }

            return o[text.Length..];
        }

        [System.Runtime.CompilerServices.MethodImpl(System.Runtime.CompilerServices.MethodImplOptions.AggressiveInlining)]
        private Span<byte> Track(Span<byte> o, int sourceLine)
        {
            o = Put(o, _trackPrefix, _trackPrefixWord);
            return o[_trackDigits.Write(o, sourceLine)..];
        }

        /// <summary>
        /// Takes the block just written after the chunk's content (<paramref name="bytes"/> long), starting a new
        /// chunk first when it would break a limit.
        /// </summary>
        private void Add(int bytes, int sourceLine, int motions, bool endsProgram, int words)
        {
            var reserve = _limitReserve;
            if (_chunkBlocks > 0 &&
                (_chunkBlocks >= _blocksPerChunk ||
                 _chunk.Length + bytes + reserve > _maxChunkBytes ||
                 _chunkWords + words + _tailWords > _rotWords))
            {
                // Once per chunk: the block waits aside while the full chunk is closed and handed to the writer.
                _block.Clear();
                _block.Append(_chunk.Pending(bytes));
                Flush(last: false);
                _chunk.Append(_block.Span);
            }
            else
            {
                _chunk.Commit(bytes);
            }

            if (_chunkBlocks == 0 &&
                (HeaderBytes.Length + bytes + reserve > _o.MaxChunkBytes || words + _tailWords > _o.RotWords))
            {
                var message = $"block of {bytes} bytes, ~{words} words does not fit one chunk " +
                              $"({_o.MaxChunkBytes} bytes, {_o.RotWords} words, {HeaderBytes.Length + reserve} bytes and {_tailWords} words taken by header and tail); raise --rot-words";
                var d = new Diagnostic(Severity.Error, SplitDiagnosticCodes.BlockTooBig, sourceLine, 1, message);
                throw new SplitException($"{_source}:{sourceLine}: {message}", [d], 1);
            }

            if (_chunkBlocks == 0)
            {
                _chunkFirst = sourceLine;
            }

            _lastBlockStart = _chunk.Length - bytes;
            _lastBlockEndsProgram = endsProgram;
            _chunkBlocks++;
            _chunkWords += words;
            _chunkLast = sourceLine;
            _totalBlocks++;
            _chunkMotion += motions;
            _totalMotion += motions;
        }

        private void Flush(bool last)
        {
            _ct.ThrowIfCancellationRequested();
            var words = _chunkWords;
            if (last)
            {
                // The tail goes before the program's own end code (M02/M30) when that is the last block, so the
                // end code still ends the program; otherwise after the last block.
                if (_lastBlockEndsProgram)
                {
                    _chunk.Insert(_lastBlockStart, _tail);
                }
                else
                {
                    _chunk.Append(_tail);
                }

                words += _tailWords;
            }

            _chunk.Append(FooterBytes);
            var length = _chunk.Length;
            var index = _chunks.Add(_chunkFirst, _chunkLast, _chunkBlocks, _chunkMotion, length, words);
            // The full buffer goes to the writer as it is; an empty one comes back for the next chunk.
            _chunk.Swap(_writer!.Submit(index, _chunks.FilePath(_folder, index), _chunk.Buffer, length));
            _chunk.Append(HeaderBytes);
            _chunkBlocks = 0;
            _chunkMotion = 0;
            _chunkWords = 0;
            _progress?.Report(new SplitProgress(_position, _totalBytes, _chunks.Count, _totalBlocks));
        }
    }
}
