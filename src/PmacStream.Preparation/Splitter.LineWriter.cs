using System.Runtime.CompilerServices;
using System.Runtime.InteropServices;
using System.Text;
using PmacStream.GCode;

namespace PmacStream.Preparation;

/// <content>The chunk line writer of a split: a block's words as the controller's chunk text, byte by byte.</content>
public static partial class Splitter
{
    /// <summary>
    /// Writes one block as the chunk carries it, straight into the room the <see cref="ChunkPacker"/> reserved: the
    /// tracking assignment (<c>M0==line</c>, before or after the words), <c>P500=F</c> where the program changes the
    /// feed and <c>F(P500)</c> after a move (paper feed), <c>DWELL0</c> before a program stop, the G codes first, N
    /// dropped unless kept, a leading <c>+</c> dropped. It says what the block does (moves, dwells, stops, ends the
    /// program), which codes stopped the program where, and holds the feed the variable was set to last. The
    /// splitting thread's.
    /// </summary>
    private sealed class ChunkLineWriter
    {
        private static readonly byte[] DwellZero = Encoding.ASCII.GetBytes("DWELL0");

        private readonly byte[] _feedVar;
        private readonly AsciiCounter _trackDigits = new();
        private readonly byte[] _trackPrefix;     // "M0=="
        private readonly ulong _trackPrefixWord;
        private readonly byte[] _feedSuffix;      // " F(P500)"
        private readonly ulong _feedSuffixWord;
        private readonly bool _exactTracking;
        private readonly bool _paperFeed;
        private readonly bool _keepN;
        private readonly bool _toolChangeMoves; // M06's hook moves to the profile's tool change position
        private readonly ProgramStopCodes _stops;
        private double _feedSet = double.NaN; // the feed the last P500= line set (paper feed mode)

        public ChunkLineWriter(SplitOptions options)
        {
            _feedVar = Encoding.ASCII.GetBytes(options.FeedVariable);
            var sync = SyncAssignment.Of(options);
            _trackPrefix = sync.PrefixBytes();
            _trackPrefixWord = Word8(_trackPrefix);
            _feedSuffix = Encoding.ASCII.GetBytes($" F({options.FeedVariable})");
            _feedSuffixWord = Word8(_feedSuffix);
            _exactTracking = sync.Placement == TrackingPlacement.Exact;
            _paperFeed = options.Feed == FeedMode.Paper;
            _keepN = options.KeepN;
            _toolChangeMoves = options.CheckProfile?.ToolChangePosition != null;
            _stops = ProgramStopCodes.Of(options.CheckProfile ?? MachineProfile.Default);
        }

        /// <summary>The codes whose routine stops the program, with the line of their first use (the manifest's <c>stopCodes</c>).</summary>
        public Dictionary<string, int> StopCodes { get; } = new(StringComparer.Ordinal);

        /// <summary>An upper bound of the bytes <see cref="Write"/> writes for a line of <paramref name="textLength"/> bytes and <paramref name="words"/> words.</summary>
        public int Room(int textLength, int words) => (2 * textLength) + (2 * words) + 64 + (2 * (_trackPrefix.Length + _feedSuffix.Length));

        /// <summary>The room <see cref="WriteAxisLine"/> needs for an axis line's text of <paramref name="textLength"/> bytes.</summary>
        public int AxisRoom(int textLength) => textLength + 64 + (2 * (_trackPrefix.Length + _feedSuffix.Length));

        /// <summary>Writes one block's chunk text at <paramref name="space"/>; returns its length (0: nothing for the controller).</summary>
        public int Write(Span<byte> space, ReadOnlySpan<byte> src, ReadOnlySpan<GWord> words, int lineNumber, out BlockMotion motion, out bool endsProgram, out int values)
        {
            // Hot path: spans over the batch's word list and line bytes, written straight into the chunk being
            // built; no allocation and no intermediate copy per block.
            var paperFeed = _paperFeed;
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
                if (_keepN && nIndex >= 0)
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
                    StopCodes.TryAdd(scan.StopCode!, lineNumber);
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
        /// <see cref="Write"/> for an <see cref="AxisLine"/> (<paramref name="space"/> of <see cref="AxisRoom"/> bytes):
        /// its text is already the words as emitted, so only the markers go around it. A move, so it is tracked and
        /// (paper feed) gets the feed suffix. Returns the length written; <paramref name="values"/> the words it takes.
        /// </summary>
        public int WriteAxisLine(Span<byte> space, ReadOnlySpan<byte> text, int words, int lineNumber, out int values)
        {
            // The same bytes as Write, written through one reference into the reserved space instead of span slices
            // (this runs for nearly every line): the room covers the markers' 8- and 16-byte stores.
            ref var o = ref MemoryMarshal.GetReference(space);
            var at = 0;
            values = words + 1;
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
            return at + 2;
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
    }
}
