using PmacStream.GCode;

namespace PmacStream.Jobs;

/// <summary>Whose fault a refused job step is.</summary>
public enum JobErrorKind
{
    /// <summary>The request cannot work as asked (bad settings, a missing file or job, a line with no block after it).</summary>
    BadRequest,

    /// <summary>The job cannot go on (the controller is unreachable, the program changed under a job, a split is gone).</summary>
    Failed,
}

/// <summary>A job step refused with a one-line reason for the operator.</summary>
public sealed class JobException : Exception
{
    /// <summary>Creates the exception.</summary>
    public JobException(string message, JobErrorKind kind = JobErrorKind.Failed, Exception? innerException = null)
        : base(message, innerException) => Kind = kind;

    /// <summary>Whose fault it is (the command line maps it to its exit code).</summary>
    public JobErrorKind Kind { get; }
}

/// <summary>
/// The job gate refused the program under the machine profile: the check found errors (or it cannot be cut into
/// chunks: nothing was split), or it uses codes the controller cannot run yet (<see cref="NotRunnableCodes"/>), or a job
/// would resume from a split forced past errors (<see cref="ForcedSplit"/>). Nothing was sent.
/// <see cref="Diagnostics"/> lists the findings, <see cref="ErrorCount"/> counts every error. The faces say how to go
/// on (the command line's <c>--force</c>).
/// </summary>
public sealed class ProgramRefusedException : Exception
{
    /// <summary>Creates the exception.</summary>
    public ProgramRefusedException(string sourcePath, IReadOnlyList<Diagnostic> diagnostics, int errorCount, string message, Exception? innerException = null)
        : base(message, innerException)
    {
        SourcePath = sourcePath;
        Diagnostics = diagnostics;
        ErrorCount = errorCount;
    }

    /// <summary>The program refused.</summary>
    public string SourcePath { get; }

    /// <summary>The findings, in line order (a huge list is cut; <see cref="ErrorCount"/> is not).</summary>
    public IReadOnlyList<Diagnostic> Diagnostics { get; }

    /// <summary>Errors found in all.</summary>
    public int ErrorCount { get; }

    /// <summary>The codes the controller cannot run yet, with their first line; empty when the check's errors refused it.</summary>
    public IReadOnlyDictionary<string, int> NotRunnableCodes { get; init; } = new Dictionary<string, int>();

    /// <summary>True when a job would resume from a split that was forced past the check's errors.</summary>
    public bool ForcedSplit { get; init; }

    /// <summary>The name of the machine profile the program was judged under (empty when not known).</summary>
    public string Profile { get; init; } = string.Empty;

    /// <summary>Every listed finding as <c>FILE:LINE:COL: error CODE: message</c>, with <paramref name="file"/> as the file's name.</summary>
    public IEnumerable<string> Lines(string file) => Diagnostics.Select(d => d.Format(file));
}
