!> Factor of safety by strength reduction (case key `strength_reduction`).
!>
!> Each trial runs the whole case from its start with the strength of every material that has
!> one divided by a factor F (`material_type%reduce_strength`: tan(phi) / F, c / F, Su / F),
!> into its own folder <output>/trial_<n>_F<factor> (particles, history, the mechanism in
!> ParaView). A trial fails when the largest particle displacement at tend exceeds the
!> displacement limit or when the kinetic energy at tend is above rest_ratio times its peak
!> (the ground has not come to rest: in an explicit code the counterpart of the
!> non-convergence of implicit strength reduction). factor_min must hold and factor_max must
!> fail; bisection then halves the bracket until it is narrower than the tolerance. The
!> factor of safety is the middle of the last bracket, reported with the bracket;
!> <output>/strength_reduction.csv lists every trial.
module mpm_strength_reduction
    use, intrinsic :: iso_fortran_env, only: output_unit
    use mpm_kinds, only: wp
    use mpm_error, only: error_type, fatal_error, exit_input, exit_interrupted
    use mpm_strings, only: int_text, fmt_real
    use mpm_case, only: case_type
    use mpm_case_output_fields, only: output_field_index
    use mpm_run, only: run_options_type, run_summary_type, run_case
    use mpm_solver, only: simulation_type
    use mpm_simulation, only: agree
    use mpm_parallel, only: image_id, max_over_images
    use mpm_filesystem, only: make_directory, directory_exists, folder_lock_type, lock_folder, &
        text_file_type, open_text_file, put_line, close_text_file
    implicit none
    private
    public :: trial_type, strength_reduction_result_type, run_strength_reduction
    public :: reduce_case_strength, trial_fails

    !> One trial of the analysis.
    type :: trial_type
        real(wp) :: factor = 1.0_wp
            !! strength reduction factor F [-]
        real(wp) :: displacement = 0.0_wp
            !! largest particle displacement at tend [m]
        real(wp) :: kinetic_ratio = 0.0_wp
            !! kinetic energy at tend / its peak over the run [-]
        logical :: fails = .false.
            !! the verdict of the criterion
        character(len=:), allocatable :: folder
            !! its output folder
    end type trial_type

    !> The outcome of the analysis.
    type :: strength_reduction_result_type
        type(trial_type), allocatable :: trials(:)
            !! every trial, in the order run
        real(wp) :: holds = 0.0_wp
            !! largest factor at which the ground held (0: it failed at factor_min, the only
            !! trial) [-]
        real(wp) :: fails = 0.0_wp
            !! smallest factor at which it failed (0: it held at factor_max) [-]
        real(wp) :: factor_of_safety = 0.0_wp
            !! middle of the bracket (0 when none was found) [-]
    end type strength_reduction_result_type

contains

    !> Run the analysis of a case with `strength_reduction`; the trials' folders, the table
    !> and a summary on standard output (image 1).
    subroutine run_strength_reduction(case, options, outcome, error)
        type(case_type), intent(in) :: case
            !! resolved case, strength_reduction enabled
        type(run_options_type), intent(in) :: options
            !! how to run (the trials run quietly)
        type(strength_reduction_result_type), intent(out) :: outcome
            !! the trials and the factor of safety
        type(error_type), allocatable, intent(out) :: error
            !! set on any failure of a trial (the analysis stops there)

        type(folder_lock_type) :: lock
        type(run_options_type) :: quiet_options
        real(wp) :: low, high
        logical :: lead
        character(len=:), allocatable :: dir

        lead = image_id() == 1
        dir = case%output%directory
        allocate (outcome%trials(0))
        if (lead) then
            if (directory_exists(dir) .and. .not. case%output%overwrite) then
                call fatal_error(error, "output folder '"//dir//"' exists already; mpm_geo " &
                    //"does not overwrite results: pass --overwrite (or set ""output"": " &
                    //"{""overwrite"": true}), or choose another folder with --output DIR", &
                    exit_input)
            end if
            if (.not. allocated(error)) call make_directory(dir, error)
            if (.not. allocated(error)) call lock_folder(dir, lock, error)
        end if
        call agree(error)
        if (allocated(error)) return
        quiet_options = options
        quiet_options%quiet = .true.
        associate (srm => case%strength_reduction)
            if (lead .and. .not. options%quiet) write (output_unit, "(a)") "mpm_geo: " &
                //case%name//": factor of safety by strength reduction, trials between " &
                //fmt_real(srm%factor_min)//" and "//fmt_real(srm%factor_max)
            low = srm%factor_min
            high = srm%factor_max
            call trial(low, error)
            if (allocated(error)) return
            if (outcome%trials(1)%fails) then
                outcome%fails = low
                call finish(error)
                return
            end if
            call trial(high, error)
            if (allocated(error)) return
            if (.not. outcome%trials(2)%fails) then
                outcome%holds = high
                call finish(error)
                return
            end if
            do while (high - low > srm%tolerance)
                call trial(0.5_wp*(low + high), error)
                if (allocated(error)) return
                if (outcome%trials(size(outcome%trials))%fails) then
                    high = outcome%trials(size(outcome%trials))%factor
                else
                    low = outcome%trials(size(outcome%trials))%factor
                end if
            end do
            outcome%holds = low
            outcome%fails = high
            outcome%factor_of_safety = 0.5_wp*(low + high)
        end associate
        call finish(error)

    contains

        !> Run one trial at factor f and judge it.
        subroutine trial(f, error)
            real(wp), intent(in) :: f
                !! the factor F [-]
            type(error_type), allocatable, intent(out) :: error
                !! the trial's failure, if any

            type(case_type) :: reduced
            type(simulation_type) :: sim
            type(run_summary_type) :: summary
            type(trial_type) :: t
            character(len=12) :: label

            reduced = case
            call reduce_case_strength(reduced, f)
            write (label, "(f0.4)") f
            if (label(1:1) == ".") label = "0"//label
            t%factor = f
            t%folder = dir//"/trial_"//int_text(size(outcome%trials) + 1)//"_F"//trim(label)
            reduced%output%directory = t%folder
            ! the displacement the criterion reads
            reduced%output%fields(output_field_index("displacement")) = .true.
            call run_case(reduced, quiet_options, sim, summary, error)
            if (allocated(error)) then
                if (error%code == exit_interrupted .and. len(error%message) > 0) then
                    ! a trial's checkpoint cannot continue the analysis (--restart runs one case)
                    error%message = "strength reduction stopped by a signal in trial " &
                        //int_text(size(outcome%trials) + 1)//" (F = "//fmt_real(f)//"); the " &
                        //"trials so far are in "//dir//"; run the analysis again to finish it"
                else if (len(error%message) > 0) then
                    error%message = "strength reduction trial at F = "//fmt_real(f)//": " &
                        //error%message
                end if
                return
            end if
            t%displacement = 0.0_wp
            if (sim%particles%n > 0) t%displacement = maxval(norm2(sim%particles%u(:, 1:sim%particles%n), &
                dim=1))
            call max_over_images(t%displacement)
            t%kinetic_ratio = summary%final_kinetic/max(summary%peak_kinetic, tiny(1.0_wp))
            t%fails = trial_fails(t%displacement, t%kinetic_ratio, &
                case%strength_reduction%displacement_limit, case%strength_reduction%rest_ratio)
            outcome%trials = [outcome%trials, t]
            if (lead .and. .not. options%quiet) write (output_unit, "(a)") "  trial " &
                //int_text(size(outcome%trials))//": F = "//trim(label)//", largest displacement " &
                //fmt_real(t%displacement, 3)//" m, kinetic energy at tend " &
                //fmt_real(t%kinetic_ratio, 2)//" of its peak: "//trim(merge("fails", "holds", &
                t%fails))
        end subroutine trial

        !> The table of the trials and the verdict.
        subroutine finish(error)
            type(error_type), allocatable, intent(out) :: error
                !! set when the table cannot be written

            type(text_file_type) :: table
            character(len=:), allocatable :: verdict
            integer :: k

            associate (srm => case%strength_reduction, trials => outcome%trials)
                if (trials(1)%fails) then
                    verdict = "the ground fails already at factor_min = "//fmt_real(srm%factor_min) &
                        //": its factor of safety is below it (lower factor_min)"
                else if (.not. trials(size(trials))%fails .and. size(trials) == 2) then
                    verdict = "the ground holds at factor_max = "//fmt_real(srm%factor_max) &
                        //": its factor of safety is above it (raise factor_max)"
                else
                    verdict = "factor of safety "//fmt_real(outcome%factor_of_safety, 4) &
                        //" (holds at "//fmt_real(outcome%holds, 5)//", fails at " &
                        //fmt_real(outcome%fails, 5)//")"
                end if
            end associate
            if (.not. lead) return
            call open_text_file(dir//"/strength_reduction.csv", table, error)
            if (allocated(error)) return
            call put_line(table, "trial,factor,displacement,kinetic_ratio,fails,folder")
            do k = 1, size(outcome%trials)
                associate (t => outcome%trials(k))
                    call put_line(table, int_text(k)//","//fmt_real(t%factor, 8)//"," &
                        //fmt_real(t%displacement, 8)//","//fmt_real(t%kinetic_ratio, 6)//"," &
                        //trim(merge("1", "0", t%fails))//","//t%folder)
                end associate
            end do
            call close_text_file(table, error)
            if (allocated(error)) return
            if (.not. options%quiet) write (output_unit, "(a)") "mpm_geo: "//case%name//": " &
                //verdict//"; trials in "//dir//"/strength_reduction.csv"
        end subroutine finish

    end subroutine run_strength_reduction

    !> The strength of every material of a case divided by F.
    subroutine reduce_case_strength(case, factor)
        type(case_type), intent(inout) :: case
            !! the case (its materials' laws)
        real(wp), intent(in) :: factor
            !! strength reduction factor F [-]

        integer :: i
        logical :: reduced

        do i = 1, size(case%materials)
            if (allocated(case%materials(i)%law)) call case%materials(i)%law%reduce_strength( &
                factor, reduced)
        end do
    end subroutine reduce_case_strength

    !> The criterion: a trial fails when the ground moved more than the limit or is still moving.
    pure logical function trial_fails(displacement, kinetic_ratio, limit, rest_ratio)
        real(wp), intent(in) :: displacement
            !! largest particle displacement at tend [m]
        real(wp), intent(in) :: kinetic_ratio
            !! kinetic energy at tend / its peak [-]
        real(wp), intent(in) :: limit
            !! displacement limit [m]
        real(wp), intent(in) :: rest_ratio
            !! largest kinetic ratio of a ground at rest [-]

        trial_fails = displacement > limit .or. kinetic_ratio > rest_ratio
    end function trial_fails

end module mpm_strength_reduction
