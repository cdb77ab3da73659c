using PmacStream.Plc;

namespace PmacStream.IntegrationTests.Plc;

/// <summary>
/// Something that runs a generated PLC program: the test sets the physical input word, runs scans and reads the
/// physical output word, like a hand on the terminal block.
/// </summary>
public interface IPlcRig
{
    /// <summary>Sets the physical inputs word (bits as wired).</summary>
    void SetInputs(long word);

    /// <summary>Runs one PLC scan.</summary>
    void Scan();

    /// <summary>Reads the physical outputs word.</summary>
    long Outputs { get; }

    /// <summary>Captures everything the program keeps between scans (I/O words and images).</summary>
    object Snapshot();

    /// <summary>Puts a captured state back.</summary>
    void Restore(object snapshot);

    /// <summary>Clears the I/O words and images, as at power-up (open memory is zeroed).</summary>
    void PowerUp();
}

/// <summary>Runs the generated lines in the Core test evaluator (independent of the simulator).</summary>
public sealed class EvaluatorRig : IPlcRig
{
    private readonly PlcEvaluator _ev;
    private readonly IoWordConfig _in;
    private readonly IoWordConfig _out;
    private readonly int[] _stateWords;

    public EvaluatorRig(LadderProgram program, GeneratedPlc generated)
    {
        _ev = PlcEvaluator.Load(generated.DownloadLines);
        _in = program.Inputs;
        _out = program.Outputs;
        _stateWords = [program.Inputs.ImageAddress, program.Outputs.ImageAddress, program.Internals.Address, program.Internals.Address + 1];
    }

    public void SetInputs(long word)
    {
        var mask = ((1L << _in.Width) - 1) << _in.Offset;
        var w = _ev.ReadWord(_in.Memory, _in.WordAddress);
        _ev.WriteWord(_in.Memory, _in.WordAddress, (w & ~mask) | ((word << _in.Offset) & mask));
    }

    public void Scan() => _ev.Scan();

    public long Outputs => (_ev.ReadWord(_out.Memory, _out.WordAddress) >> _out.Offset) & ((1L << _out.Width) - 1);

    public object Snapshot() =>
        (_ev.ReadWord(_in.Memory, _in.WordAddress), _ev.ReadWord(_out.Memory, _out.WordAddress), _stateWords.Select(a => _ev.ReadWord('Y', a)).ToArray());

    public void PowerUp() => Restore(((long)0, (long)0, new long[_stateWords.Length]));

    public void Restore(object snapshot)
    {
        var (i, o, words) = ((long, long, long[]))snapshot;
        _ev.WriteWord(_in.Memory, _in.WordAddress, i);
        _ev.WriteWord(_out.Memory, _out.WordAddress, o);
        for (var k = 0; k < words.Length; k++)
        {
            _ev.WriteWord('Y', _stateWords[k], words[k]);
        }
    }
}
